// Explicit integration (paper Algorithm 1: sumForces, computeNewPosition): symplectic Euler.
// Damping is applied implicitly, v <- v / (1 + c dt), which removes energy at any dt and adds no
// stability limit of its own; the elastic limit is dt < 2/omega_max (Model::stable_dt_estimate).
//
// The arrays are read through local pointers: through the State/Model references the compiler
// must assume each store may move a vector's buffer and reloads every data pointer per particle.
#include <algorithm>
#include <cstring>

#include "engine/step/stages.h"

namespace ps {

void integrate(const Model& m, State& s, double dt) {
  const int n = m.particle_count();
  const double* inv_mass = m.inv_mass.data();
  const double* damping = m.damping.data();
  const Vec3* f = s.f.data();
  Vec3* x = s.x.data();
  Vec3* v = s.v.data();
  std::copy(x, x + n, s.x_prev.data());
  std::memset(s.contact.data(), 0, static_cast<size_t>(n));  // contacts are found again by this step's constraints
  for (int p = 0; p < n; ++p) {
    const double im = inv_mass[p];
    if (im == 0.0) continue;  // rigid or kinematic: placed by its body or constraint
    v[p] = (v[p] + dt * im * f[p]) / (1.0 + damping[p] * dt);
    x[p] += dt * v[p];
  }
}

void adjust_velocities(State& s, double dt) {
  const double inv_dt = 1.0 / dt;
  const size_t n = s.x.size();
  const Vec3* x = s.x.data();
  const Vec3* xp = s.x_prev.data();
  Vec3* v = s.v.data();
  for (size_t p = 0; p < n; ++p) v[p] = (x[p] - xp[p]) * inv_dt;
}

}  // namespace ps
