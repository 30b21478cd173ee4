// Empirical stability limit of the explicit step vs Model::stable_dt_estimate
// (compile_time_step.cpp estimate_stable_dt: 2/sqrt(lambda_max(M^-1 K)) of the undamped linearisation at
// rest, by power iteration). Every scene is compiled with damping 0 and stepped with a substep
// of fraction * estimate, bypassing the automatic substepping (step(h) takes any h; the model's
// dt/substeps are not used). Two regimes:
//   linear   gravity off, every free coordinate displaced by uniform noise of +-1 um, at rest;
//            unstable when some particle gets 100 um from rest (or the check faults) within
//            `steps` substeps. This is exactly what the estimate predicts.
//   gravity  the scene as written (gravity on), from rest, for 1 s of simulated time;
//            unstable when the check faults (NaN, speed > 50 m/s, excursion > 1 m). Large
//            undamped swings, so this also shows how far the at-rest estimate carries into large
//            deformation; the peak kinetic energy is printed next to the work gravity can do.
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <iterator>
#include <random>
#include <vector>

#include "bench/bench_modes.h"
#include "bench/scenes.h"

namespace ps::bench {

namespace {

constexpr double kNoise = 1e-6;        // initial displacement amplitude, linear regime [m]
constexpr double kGrown = 1e-4;        // displacement that counts as growth [m]
constexpr double kGravityTime = 1.0;   // simulated time of the gravity regime [s]

struct Outcome {
  bool stable = true;
  long steps = 0;            // substeps run
  std::string why;           // fault or growth, when unstable
  double peak_ke = 0.0;      // largest kinetic energy seen (gravity regime) [J]
};

Outcome run_linear(const std::shared_ptr<const Model>& m, double h, int steps) {
  Simulation sim(m);
  State& s = sim.state();
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> U(-kNoise, kNoise);
  for (int p = 0; p < m->particle_count(); ++p)
    for (int a = 0; a < 3; ++a)
      if (m->inv_mass[p] > 0.0 && !(m->locked_axes[p] & (1u << a))) s.x[p][a] += U(rng);
  Outcome o;
  for (int i = 0; i < steps; ++i) {
    o.steps = i + 1;
    if (!sim.step(h)) { o.stable = false; o.why = s.fault.describe(*m); return o; }
    if (i % 50 == 49) {
      double d2 = 0;
      for (int p = 0; p < m->particle_count(); ++p) d2 = std::max(d2, (s.x[p] - m->rest_pos[p]).squaredNorm());
      if (d2 > kGrown * kGrown) {
        o.stable = false;
        o.why = "displacement grew from 1 um to " + std::to_string(std::sqrt(d2) * 1e6) + " um";
        return o;
      }
    }
  }
  return o;
}

Outcome run_gravity(const std::shared_ptr<const Model>& m, double h) {
  Simulation sim(m);
  Outcome o;
  const long steps = std::lround(kGravityTime / h);
  for (long i = 0; i < steps; ++i) {
    o.steps = i + 1;
    if (!sim.step(h)) { o.stable = false; o.why = sim.state().fault.describe(*m); return o; }
    o.peak_ke = std::max(o.peak_ke, kinetic_energy(*m, sim.state()));
  }
  return o;
}

std::shared_ptr<const Model> compile_with(const std::string& name, bool gravity) {
  ScenarioSpec spec = parse_scenario_text(scene_text(name, 0.0), "stable_dt.yaml");
  if (!gravity) spec.gravity = Vec3::Zero();
  return compile_scenario(spec);
}

}  // namespace

int stable_dt_study(int steps) {
  std::printf("stability study: damping 0; linear regime %d substeps from +-1 um noise without gravity, "
              "gravity regime %.2f s from rest\n", steps, kGravityTime);
  const char* const scenes[] = {"cube11", "cube11i", "cube11s", "cube11si", "cyl", "cyli"};
  const double linear_fractions[] = {0.5, 0.9, 1.0, 1.1, 1.5, 2.0};
  const double gravity_fractions[] = {0.1, 0.25, 0.5, 0.9, 1.0, 1.1, 1.5, 2.0};
  for (const char* name : scenes) {
    for (bool gravity : {false, true}) {
      auto m = compile_with(name, gravity);
      const double est = m->stable_dt_estimate;
      const char* regime = gravity ? "gravity" : "linear";
      auto run = [&](double f) { return gravity ? run_gravity(m, f * est) : run_linear(m, f * est, steps); };
      std::printf("\n%s, %s regime: %d particles, estimate %.6g s\n", name, regime, m->particle_count(), est);
      if (gravity) {
        // yardstick for the kinetic energy of an honest swing: gravity can do at most about
        // m g L/2 of work (L = the body's largest extent; its centre of mass cannot fall further
        // while the body barely stretches)
        double mass = 0;
        Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
        for (int p = 0; p < m->particle_count(); ++p) {
          mass += m->mass[p];
          lo = lo.cwiseMin(m->rest_pos[p]);
          hi = hi.cwiseMax(m->rest_pos[p]);
        }
        std::printf("  (gravity can do at most ~m g L/2 = %.3g J of work)\n",
                    0.5 * mass * m->gravity.norm() * (hi - lo).maxCoeff());
      }
      for (double f : gravity ? std::vector<double>(std::begin(gravity_fractions), std::end(gravity_fractions))
                              : std::vector<double>(std::begin(linear_fractions), std::end(linear_fractions))) {
        const Outcome o = run(f);
        if (o.stable) std::printf("  %.2f x estimate: stable (%ld substeps)", f, o.steps);
        else std::printf("  %.2f x estimate: UNSTABLE after %ld substeps: %s", f, o.steps, o.why.c_str());
        if (gravity) std::printf(", peak kinetic energy %.3g J", o.peak_ke);
        std::printf("\n");
        std::fflush(stdout);
      }
      if (gravity) continue;  // large undamped swings are not monotone in dt: no bisection
      // bisection on the fraction between a stable lo and an unstable hi
      double lo = 0.5, hi = 2.0;
      if (!run(lo).stable || run(hi).stable) { std::printf("  no bracket in [0.5, 2]\n"); continue; }
      while (hi - lo > 0.005) {
        const double mid = 0.5 * (lo + hi);
        (run(mid).stable ? lo : hi) = mid;
      }
      std::printf("  %s %s: largest stable substep %.3f..%.3f x estimate\n", name, regime, lo, hi);
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace ps::bench
