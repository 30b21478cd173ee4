// Rigid-bodies stage of compile_scenario: elastic particles get their inverse mass and shape
// memory; each rigid component becomes a RigidBody (mass, centre of mass, inertia) whose particles
// are locked on every axis.
#include "engine/scenario/compile_stages.h"

namespace ps {

void compile_rigid_bodies(const ScenarioSpec& spec, Model& m) {
  const int n = m.particle_count();
  // rigid components become bodies
  m.inv_mass.assign(n, 0.0);
  m.shape_memory.assign(n, 0);
  m.locked_axes.assign(n, 0);
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    Component& comp = m.components[ci];
    const int b = comp.first_particle, e = b + comp.particle_count;
    if (comp.kind != ComponentKind::Rigid) {
      for (int p = b; p < e; ++p) { m.inv_mass[p] = 1.0 / m.mass[p]; m.shape_memory[p] = 1; }
      continue;
    }
    RigidBody rb;
    rb.component = static_cast<int>(ci);
    rb.kinematic = spec.components[ci].kinematic;
    for (int p = b; p < e; ++p) { rb.mass += m.mass[p]; rb.com_rest += m.mass[p] * m.rest_pos[p]; }
    rb.com_rest /= rb.mass;
    rb.inertia_body.setZero();
    for (int p = b; p < e; ++p) {
      const Vec3 r = m.rest_pos[p] - rb.com_rest;
      rb.particles.push_back(p);
      rb.local.push_back(r);
      rb.inertia_body += m.mass[p] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
      m.locked_axes[p] = 7;
    }
    comp.rigid_body = static_cast<int>(m.rigid_bodies.size());
    m.rigid_bodies.push_back(std::move(rb));
  }
}

}  // namespace ps
