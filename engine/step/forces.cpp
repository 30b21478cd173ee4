// External forces: gravity (force field) and locally applied forces (paper §3.1).
#include <algorithm>

#include "engine/step/stages.h"

namespace ps {

double ramp_fraction(double t, double t0, double t1) {
  if (t1 <= t0) return t >= t0 ? 1.0 : 0.0;
  return std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
}

void clear_and_add_external_forces(const Model& m, State& s, double t) {
  const int n = m.particle_count();
  // raw pointers: through m and s the compiler reloads both buffers for every particle
  const double* mass = m.mass.data();
  const Vec3 g = m.gravity;
  Vec3* f = s.f.data();
  for (int p = 0; p < n; ++p) f[p] = mass[p] * g;
  for (const AppliedForce& af : m.applied_forces) {
    const Vec3 each = ramp_fraction(t, af.t0, af.t1) * af.total / static_cast<double>(af.particles.size());
    for (int p : af.particles) s.f[p] += each;
  }
  for (auto& b : s.bodies) { b.force.setZero(); b.torque.setZero(); }
}

}  // namespace ps
