// Stiffness-proportional (Rayleigh) damping, Model::stiffness_damping = beta (docs/model.md
// "Stiffness damping"). The elastic stages between DampingShift and DampingUnshift (and the
// multi-rate slow group's force at the tick's end) see the positions x + beta v, so each elastic
// force f(x) becomes f(x + beta v) = f(x) - beta K v + O(beta^2 |v|^2): the damping force of
// C = beta K without a second element pass. The true positions wait in State::x_shift and come
// back with the swap (two buffer swaps, no copy of them, no allocation). A rigid translation shifts
// every particle by the same beta v and gets no force, as C = beta K gives none; at rest the shift
// is zero, so x + beta v is x bit for bit and a scene at rest stays exactly at rest.
#include "engine/step/stages.h"

namespace ps {

void shift_for_damping(const Model& m, State& s) {
  const double beta = m.stiffness_damping;  // [s]
  Vec3* xs = s.x_shift.data();
  const Vec3* x = s.x.data();
  const Vec3* v = s.v.data();
  for (int p = 0, n = m.particle_count(); p < n; ++p) xs[p] = x[p] + beta * v[p];
  s.x.swap(s.x_shift);  // x: the shifted positions; x_shift: the true ones
}

void unshift_for_damping(State& s) { s.x.swap(s.x_shift); }

}  // namespace ps
