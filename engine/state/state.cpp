#include "engine/state/state.h"

#include <algorithm>
#include <cstring>
#include <sstream>

namespace ps {

State make_state(const Model& model) {
  const size_t n = model.rest_pos.size();
  State s;
  s.x = model.rest_pos;
  s.v.assign(n, Vec3::Zero());
  s.f.assign(n, Vec3::Zero());
  s.x_prev = model.rest_pos;
  if (model.stiffness_damping > 0.0) s.x_shift = model.rest_pos;
  s.attractor = model.rest_pos;
  s.volume_grad.assign(n, Vec3::Zero());
  s.contact.assign(n, 0);
  s.triplet_scratch.assign(static_cast<size_t>(kTripletScratchFields) * 4 * model.most_chunks, 0.0);
  s.strain_rot.assign(model.strain.centre.size(), Quat::Identity());
  s.tet_node_vol.assign(model.tets.nodes.size(), 0.0);
  // with the -0.0 padding slot of the node volumes' gather at the end (TetElements::gather_elem)
  s.tet_quarter.assign(model.tets.count() + 1, -0.0);
  s.tet_edges.assign(9 * static_cast<size_t>(model.tets.count()), 0.0);
  if (const int k = model.tet_pressure.size(); k > 0) {
    s.pressure_rhs.assign(k, 0.0);
    s.pressure_work.assign(k, 0.0);
    s.pressure_lambda.assign(k, 0.0);
    s.pressure_dx.assign(n, Vec3::Zero());
    s.pressure_quarter.assign(model.tet_pressure.tets.size(), 0.0);
  }
  if (model.tets.multirate()) {
    s.tet_slow_vol.assign(model.tets.nodes.size(), 0.0);
    s.tet_slow_f.assign(model.rest_pos.size(), Vec3::Zero());
    s.tet_slow_hold.assign(model.rest_pos.size(), Vec3::Zero());
  }
  if (model.sleep.enabled()) {  // everything awake: every element evaluated, nothing held
    const int nt = model.tets.count();
    s.asleep.assign(n, 0);
    s.quiet_ticks.assign(n, 0);
    s.tet_order.resize(nt);
    for (int t = 0; t < nt; ++t) s.tet_order[t] = t;
    s.tet_awake_count = nt;
    s.tet_held_vol.assign(model.tets.nodes.size(), 0.0);
    s.tet_held_f.assign(n, Vec3::Zero());
  }
  s.bodies.resize(model.rigid_bodies.size());
  for (size_t b = 0; b < model.rigid_bodies.size(); ++b) s.bodies[b].com = model.rigid_bodies[b].com_rest;
  s.target_volume.resize(model.surfaces.size());
  for (size_t i = 0; i < model.surfaces.size(); ++i) s.target_volume[i] = model.surfaces[i].rest_volume;
  s.last_lambda.assign(model.surfaces.size(), 0.0);
  s.activation.assign(model.components.size(), 0.0);
  return s;
}

namespace {
inline void fnv(uint64_t& h, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) { h ^= p[i]; h *= 1099511628211ull; }
}
}  // namespace

uint64_t hash_state(const State& s) {
  uint64_t h = 1469598103934665603ull;
  fnv(h, &s.time, sizeof s.time);
  for (const Vec3& p : s.x) fnv(h, p.data(), 3 * sizeof(double));
  for (const Vec3& p : s.v) fnv(h, p.data(), 3 * sizeof(double));
  for (const auto& b : s.bodies) {
    fnv(h, b.com.data(), 3 * sizeof(double));
    fnv(h, b.rot.coeffs().data(), 4 * sizeof(double));
  }
  return h;
}

double kinetic_energy(const Model& m, const State& s) {
  double e = 0.0;
  for (size_t i = 0; i < s.v.size(); ++i) e += 0.5 * m.mass[i] * s.v[i].squaredNorm();
  return e;
}

double max_speed(const State& s) {
  double v2 = 0.0;
  for (const Vec3& v : s.v) v2 = std::max(v2, v.squaredNorm());
  return std::sqrt(v2);
}

std::string StepFault::describe(const Model& m) const {
  std::ostringstream o;
  o << "t=" << time << " s: ";
  if (particle >= 0 && particle < m.particle_count())
    o << "particle " << particle << " (component '" << m.components[m.component_of[particle]].name << "') ";
  switch (kind) {
    case None: o << "no fault"; break;
    case NotFinite: o << "position or velocity is NaN/Inf"; break;
    case TooFast: o << "speed " << value << " m/s exceeds the blow-up limit " << m.max_speed << " m/s"; break;
    case TooFar: o << "moved " << value << " m from rest, beyond the blow-up limit " << m.max_excursion << " m"; break;
    case VolumeSolve: o << "volume constraint has no real solution near the current shape"; break;
  }
  return o.str();
}

}  // namespace ps
