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

namespace {
typedef double D2 __attribute__((vector_size(16)));
typedef double U2 __attribute__((vector_size(16), aligned(8), may_alias));  // unaligned view
inline D2 load2(const double* p) { return *reinterpret_cast<const U2*>(p); }
inline void store2(double* p, D2 v) { *reinterpret_cast<U2*>(p) = v; }
}  // namespace

namespace {
// Asleep: the sleeping-tissue variant (State::asleep, tet_sleep.cpp), whose sleeping particles
// stay where they are; a scene without sleeping tissue runs the loop without the test.
template <bool Asleep>
void integrate_particles(const Model& m, State& s, double dt) {
  const int n = m.particle_count();
  const uint8_t* asleep = s.asleep.data();
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
    if constexpr (Asleep) {
      if (asleep[p]) continue;  // v is 0 and stays 0 while it sleeps
    }
    // v = (v + dt im f) / (1 + c dt), x += dt v: x and y as one 2-lane operation (the same IEEE
    // operations as three scalar ones: one division instruction fewer)
    const double a = dt * im, d = 1.0 + damping[p] * dt;
    double* vp = v[p].data();
    double* xp = x[p].data();
    const double* fp = f[p].data();
    const D2 vxy = (load2(vp) + D2{a, a} * load2(fp)) / D2{d, d};
    const double vz = (vp[2] + a * fp[2]) / d;
    store2(vp, vxy);
    vp[2] = vz;
    store2(xp, load2(xp) + D2{dt, dt} * vxy);
    xp[2] += dt * vz;
  }
}
}  // namespace

void integrate(const Model& m, State& s, double dt) {
  if (s.asleep.empty()) integrate_particles<false>(m, s, dt);
  else integrate_particles<true>(m, s, dt);
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
