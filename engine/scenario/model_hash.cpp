#include "engine/scenario/model_hash.h"

#include "engine/scenario/material_models.h"

#include <string>
#include <vector>

namespace ps {


uint64_t model_hash(const Model& m) {
  ModelHasher f;
  f.pod(m.dt);
  f.pod(m.substeps);
  f.pod(m.duration);
  for (int k = 0; k < 3; ++k) f.pod(m.gravity[k]);
  f.pod(m.redistribution);
  for (const Vec3& p : m.rest_pos) for (int k = 0; k < 3; ++k) f.pod(p[k]);
  f.vec(m.mass);
  f.vec(m.k_e);
  f.vec(m.k_c);
  f.vec(m.k_f);
  f.vec(m.damping);
  f.vec(m.component_of);
  f.vec(m.on_surface);
  f.vec(m.locked_axes);
  f.vec(m.nbr_start);
  f.vec(m.nbr);
  f.vec(m.nbr_w);
  for (const BetaTriplet& b : m.beta) { f.pod(b.i); f.pod(b.j); f.pod(b.k); f.pod(b.b); }
  for (const std::string& t : m.tag_names) f.str(t);
  f.vec(m.particle_tags);
  // a role only where `role:` gives another than the name's default: a scene that names its organs
  // keeps its hash, and an edit of a role is a different compiled scene
  for (size_t t = 0; t < m.tag_roles.size() && t < m.tag_names.size(); ++t)
    if (m.tag_roles[t] != default_role(m.tag_names[t], false)) { f.pod(t); f.pod(m.tag_roles[t]); }
  for (const Component& c : m.components) {
    f.str(c.name);
    f.pod(c.kind);
    f.pod(c.spacing);
    f.pod(c.active_force);
    if (c.role != default_role(c.name, c.kind == ComponentKind::Rigid)) f.pod(c.role);
  }
  for (const Surface& s : m.surfaces) {
    f.vec(s.vertices);
    for (const auto& t : s.faces) f.pod(t);
    f.pod(s.rest_volume);
    f.pod(s.volume_constrained);
  }
  // each material model's elements, rest data and materials (an edit of a tet or shell material
  // changes nothing above), in MaterialModel order
  for (const MaterialModelDesc* d : material_models())
    if (d->hash) d->hash(m, f);
  if (m.stiffness_damping > 0.0) f.pod(m.stiffness_damping);  // only then: the undamped scenes keep their hash
  if (m.sleep.enabled()) {  // only then: a scene without sleeping tissue keeps its hash
    f.vec(m.sleep.role);
    f.pod(m.sleep.wake_accel);
    f.pod(m.sleep.sleep_accel);
    f.pod(m.sleep.sleep_speed);
    f.pod(m.sleep.hold_ticks);
  }
  for (const FixedParticle& p : m.fixed) { f.pod(p.particle); f.pod(p.axes); }
  for (const ImposedDisplacement& d : m.imposed) {
    f.vec(d.particles);
    for (int k = 0; k < 3; ++k) f.pod(d.by[k]);
    f.pod(d.t0);
    f.pod(d.t1);
  }
  for (const HalfSpace& h : m.half_spaces) f.vec(h.particles);
  for (const AppliedForce& a : m.applied_forces) {
    f.vec(a.particles);
    for (int k = 0; k < 3; ++k) f.pod(a.total[k]);
  }
  return f.value();
}

}  // namespace ps
