// Numerical check after each substep: NaN/Inf, speed and excursion limits. The first offending
// particle is recorded with the time so the caller can stop and report (never a silent NaN file).
#include <cmath>

#include "engine/step/stages.h"

namespace ps {

namespace {
// The full test of one particle, in the order faults are reported.
bool check_particle(const Model& m, State& s, int p, double v2max, double d2max) {
  const Vec3& x = s.x[p];
  const Vec3& v = s.v[p];
  if (!(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]) && std::isfinite(v[0]) &&
        std::isfinite(v[1]) && std::isfinite(v[2]))) {
    s.fault = StepFault{StepFault::NotFinite, p, s.time, 0.0};
    return false;
  }
  const double v2 = v.squaredNorm();
  if (v2 > v2max) { s.fault = StepFault{StepFault::TooFast, p, s.time, std::sqrt(v2)}; return false; }
  const double d2 = (x - m.rest_pos[p]).squaredNorm();
  if (d2 > d2max) { s.fault = StepFault{StepFault::TooFar, p, s.time, std::sqrt(d2)}; return false; }
  return true;
}
}  // namespace

bool check_state(const Model& m, State& s) {
  const int n = m.particle_count();
  const double v2max = m.max_speed * m.max_speed;
  const double d2max = m.max_excursion * m.max_excursion;
  const Vec3* x = s.x.data();
  const Vec3* v = s.v.data();
  const Vec3* rest = m.rest_pos.data();
  for (int p = 0; p < n; ++p) {
    // Fast path: both comparisons are false for NaN, and an infinite or NaN coordinate makes v2
    // or d2 infinite or NaN (rest positions are finite), so a particle passing them passes every
    // test; any other particle gets the full test, which reports exactly what it did before.
    const double v2 = v[p].squaredNorm();
    const double d2 = (x[p] - rest[p]).squaredNorm();
    if (v2 <= v2max && d2 <= d2max) continue;
    if (!check_particle(m, s, p, v2max, d2max)) return false;
  }
  return true;
}

}  // namespace ps
