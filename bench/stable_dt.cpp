// Empirical stability limit of the explicit step vs Model::stable_dt_estimate
// (compile.cpp estimate_stable_dt: 2/sqrt(lambda_max(M^-1 K)) of the undamped linearisation).
// Each scene is compiled with damping 0 and stepped from rest under gravity with a substep of
// fraction * estimate, bypassing the automatic substepping (step(h) takes any h). "stable" means
// no fault (NaN, speed > 50 m/s, excursion > 1 m) within the given number of substeps.
#include <cstdio>

#include "bench/bench_modes.h"
#include "bench/scenes.h"

namespace ps::bench {

namespace {
// substeps run before the first fault, or -1 when all `steps` ran
long first_fault(const std::shared_ptr<const Model>& m, double h, int steps, std::string* why) {
  Simulation sim(m);
  for (int i = 0; i < steps; ++i)
    if (!sim.step(h)) {
      if (why) *why = sim.state().fault.describe(*m);
      return i;
    }
  return -1;
}
}  // namespace

int stable_dt_study(int steps) {
  std::printf("stability study: damping 0, from rest under gravity, %d substeps per run\n", steps);
  const char* const scenes[] = {"cube11", "cube11i", "cyl", "cyli"};
  const double fractions[] = {0.5, 0.9, 1.0, 1.1, 1.5, 2.0};
  for (const char* name : scenes) {
    auto m = scene_by_name(name, 0.0);
    const double est = m->stable_dt_estimate;
    std::printf("\n%s: %d particles, estimate %.6g s\n", name, m->particle_count(), est);
    for (double f : fractions) {
      std::string why;
      const long k = first_fault(m, f * est, steps, &why);
      if (k < 0) std::printf("  %.2f x estimate (%.4g s): stable for %d substeps (%.4g s)\n", f, f * est, steps, steps * f * est);
      else std::printf("  %.2f x estimate (%.4g s): FAULT after %ld substeps: %s\n", f, f * est, k, why.c_str());
      std::fflush(stdout);
    }
    // bisection on the fraction: lo stable, hi faulted (when the bracket holds)
    double lo = 0.5, hi = 2.0;
    if (first_fault(m, lo * est, steps, nullptr) >= 0 || first_fault(m, hi * est, steps, nullptr) < 0) {
      std::printf("  no bracket in [0.5, 2]\n");
      continue;
    }
    while (hi - lo > 0.005) {
      const double mid = 0.5 * (lo + hi);
      (first_fault(m, mid * est, steps, nullptr) < 0 ? lo : hi) = mid;
    }
    std::printf("  largest stable fraction: %.3f..%.3f x estimate (%.4g s .. %.4g s)\n", lo, hi, lo * est, hi * est);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace ps::bench
