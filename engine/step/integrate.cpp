// Explicit integration (paper Algorithm 1: sumForces, computeNewPosition): symplectic Euler.
// Damping is applied implicitly, v <- v / (1 + c dt), which removes energy at any dt and adds no
// stability limit of its own; the elastic limit is dt < 2/omega_max (Model::stable_dt_estimate).
#include "engine/step/stages.h"

namespace ps {

void integrate(const Model& m, State& s, double dt) {
  const int n = m.particle_count();
  for (int p = 0; p < n; ++p) {
    s.x_prev[p] = s.x[p];
    s.contact[p] = 0;  // contacts are found again by this step's constraints
    const double im = m.inv_mass[p];
    if (im == 0.0) continue;  // rigid or kinematic: placed by its body or constraint
    s.v[p] = (s.v[p] + dt * im * s.f[p]) / (1.0 + m.damping[p] * dt);
    s.x[p] += dt * s.v[p];
  }
}

void adjust_velocities(State& s, double dt) {
  const double inv_dt = 1.0 / dt;
  const size_t n = s.x.size();
  for (size_t p = 0; p < n; ++p) s.v[p] = (s.x[p] - s.x_prev[p]) * inv_dt;
}

}  // namespace ps
