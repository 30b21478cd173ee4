// `prostatesim_bench --fast-error SCENE SUBSTEPS MASS_SCALING TRIPLETS DURATION_S [REF_SUBSTEPS [FAST_NU
//  [FAST_PRESSURE [PRESSURE_ITERATIONS [FAST_SLEEP_WAKE [FAST_MULTIRATE [FAST_DT_MS]]]]]]]`:
// error of a fast configuration (SUBSTEPS per tick, 0 = the file's; solver.mass_scaling 0/1, -1 =
// the file's; solver.triplets = TRIPLETS, 0 = all)
// against the converged reference (the paper's scheme, every triplet, REF_SUBSTEPS per tick,
// default 2x the file's) on the scene's own needle insertion (bench/realtime_scenes.h), or in a
// scene without a needle (bladder_filling) on what the file itself does (the filling), over
// DURATION_S of simulated time. Prints the figures the budget names: needle force RMS
// error / its peak (<= 10 %), puncture depths (<= 1 mm), prostate and target displacement
// (<= 0.5 mm), volumes (exact), and whether the budget holds (exit 0) or not (exit 1).
// FAST_NU > 0 sets the prostate material's local Poisson ratio in the fast run only (the reference
// keeps the file's): the error of a softer local volume term, against the file's model.
// The reference always runs the explicit pressure (materials' `pressure: implicit` off): the
// converged explicit scheme. FAST_PRESSURE 0/1 sets the fast run's prostate material explicit/implicit
// (-1: the file's); PRESSURE_ITERATIONS > 0 sets its solver.pressure_iterations. FAST_SLEEP_WAKE
// sets the fast run's sleeping tissue: 0 off, > 0 on with that solver.sleep_wake_m_s2, < 0 (the
// default) the file's; the reference never sleeps. FAST_MULTIRATE 0/1 sets the fast run's
// solver.multirate (-1, the default: the file's); the reference never splits. FAST_DT_MS > 0 sets
// the fast run's tick (time.dt_ms; the reference keeps the file's): a longer tick at the same substep
// runs the multi-rate slow group less often. REF_FILE: the reference reads this scenario file
// instead of config/<SCENE>.yaml (the same anatomy otherwise discretised, e.g. the fat at another
// spacing: the error of the change of discretisation plus the fast scheme's). The prostate must
// keep its particles (same mesh and spacing, first component), as the comparison is per particle.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <cstdlib>

#include "bench/bench_modes.h"
#include "bench/realtime_scenes.h"
#include "engine/scenario/compile.h"
#include "engine/sim/trajectory.h"

namespace ps::bench {

int fast_error(const std::string& scene, int substeps, int mass_scaling, int triplets, double duration,
               int ref_substeps, double fast_nu, int fast_pressure, int pressure_iterations, double fast_sleep_wake,
               int fast_multirate, double fast_dt_ms, const std::string& ref_file) {
  const ScenarioSpec ref_spec0 = realtime_scene(scene, -1, -1, -1, -1, ref_file);
  if (ref_substeps <= 0) ref_substeps = 2 * ref_spec0.substeps;
  ScenarioSpec ref_spec = realtime_scene(scene, 0, ref_substeps, 0, 0, ref_file);  // plain explicit, every element every substep
  for (MaterialSpec& mat : ref_spec.materials) mat.implicit_pressure = false;
  ref_spec.sleep = false;
  ScenarioSpec fast_spec = realtime_scene(scene, triplets, substeps, mass_scaling, fast_multirate);
  if (fast_pressure >= 0)
    for (MaterialSpec& mat : fast_spec.materials)
      if (mat.name == "prostate") mat.implicit_pressure = fast_pressure != 0;
  if (fast_dt_ms > 0.0) fast_spec.dt = fast_dt_ms * 1e-3;
  if (pressure_iterations > 0) fast_spec.pressure_iterations = pressure_iterations;
  if (fast_sleep_wake == 0.0) fast_spec.sleep = false;
  if (fast_sleep_wake > 0.0) {
    fast_spec.sleep = true;
    fast_spec.sleep_wake_accel = fast_sleep_wake;
  }
  if (fast_nu > 0.0)
    for (MaterialSpec& mat : fast_spec.materials)
      if (mat.name == "prostate") mat.poisson = fast_nu;
  auto ref_model = compile_scenario(ref_spec);
  auto fast_model = compile_scenario(fast_spec);
  if (!ref_file.empty()) {
    // the per-particle comparison needs the prostate's particles where the fast run has them
    const int pr = ref_model->find_role(ps::Role::Prostate), pf = fast_model->find_role(ps::Role::Prostate);
    if (pr < 0 || pf < 0 || ref_model->components[pr].first_particle != fast_model->components[pf].first_particle ||
        ref_model->components[pr].particle_count != fast_model->components[pf].particle_count) {
      std::fprintf(stderr, "%s: the prostate's particles differ from config/%s.yaml's\n", ref_file.c_str(), scene.c_str());
      return 2;
    }
    std::printf("reference file %s: %d particles, %d tet elements\n", ref_file.c_str(), ref_model->particle_count(),
                ref_model->tets.count());
  }
  const Vec3 target = realtime_target(scene, ref_spec);
  std::printf("%s: reference all triplets, %d substeps (estimate %.4g ms); fast %d triplets, %d substeps "
              "(estimate %.4g ms), mass scaling %s (added inertia %.4g g, largest factor %.3g), multirate %s "
              "(%d of %d tet elements once per tick), implicit pressure on %d nodes x %d solve(s), sleep %s (%d particles may, wake at %.3g m/s^2); %.3f s\n",
              scene.c_str(), ref_model->substeps, ref_model->stable_dt_estimate * 1e3, triplets, fast_model->substeps,
              fast_model->stable_dt_estimate * 1e3, fast_spec.mass_scaling ? "on" : "off",
              fast_model->added_inertia * 1e3, fast_model->largest_inertia_factor, fast_spec.multirate ? "on" : "off",
              fast_model->tets.count() - fast_model->tets.fast_count, fast_model->tets.count(),
              fast_model->tet_pressure.size(), fast_model->tet_pressure.iterations, fast_model->sleep.enabled() ? "on" : "off",
              fast_model->sleep.eligible_count, fast_model->sleep.wake_accel, duration);
  std::fflush(stdout);
  const std::clock_t c0 = std::clock();
  const Trajectory ref = record_trajectory(ref_spec, ref_model, duration, target);
  const std::clock_t c1 = std::clock();
  const Trajectory fast = record_trajectory(fast_spec, fast_model, duration, target);
  const std::clock_t c2 = std::clock();
  // CPU time of each run (this process, one thread; the recording adds a little to both)
  std::printf("cpu: reference %.2f s, fast %.2f s (%.3f ms per tick, %.3g sim s per CPU s); fast run evaluated %.1f %% of "
              "the tet elements on average\n",
              double(c1 - c0) / CLOCKS_PER_SEC, double(c2 - c1) / CLOCKS_PER_SEC,
              1e3 * double(c2 - c1) / CLOCKS_PER_SEC / std::max<size_t>(1, fast.watched.size()),
              duration / std::max(1e-9, double(c2 - c1) / CLOCKS_PER_SEC), 100.0 * fast.evaluated_elements);
  if (ref.faulted || fast.faulted) {
    std::printf("fault: reference %s, fast %s\n", ref.fault.c_str(), fast.fault.c_str());
    return 1;
  }
  const TrajectoryError e = compare_trajectories(fast, ref);
  const double force_rel = e.force_peak > 0 ? e.force_rms / e.force_peak : 0.0;
  std::printf("needle force RMS error %.4g N = %.2f %% of its peak %.4g N (budget 10 %%)\n", e.force_rms,
              100 * force_rel, e.force_peak);
  std::printf("punctures: reference %zu, fast %zu, unmatched %d, largest depth difference %.3f mm (budget 1 mm)\n",
              ref.punctures.size(), fast.punctures.size(), e.puncture_mismatch, e.puncture_depth * 1e3);
  for (const PunctureRecord& p : ref.punctures)
    std::printf("  reference puncture: needle %d component %d at %.4f s, depth %.2f mm, force %.3f N\n", p.needle,
                p.component, p.time, p.depth * 1e3, p.force);
  for (const PunctureRecord& p : fast.punctures)
    std::printf("  fast puncture:      needle %d component %d at %.4f s, depth %.2f mm, force %.3f N\n", p.needle,
                p.component, p.time, p.depth * 1e3, p.force);
  std::printf("prostate displacement difference: RMS %.3f mm, max %.3f mm; target %.3f mm (budget 0.5 mm)\n",
              e.prostate_rms * 1e3, e.prostate_max * 1e3, e.target * 1e3);
  std::printf("volume error: fast %.3g, reference %.3g (exact: <= 1e-9)\n", e.volume, ref.worst_volume_error);
  const bool ok = force_rel <= 0.10 && e.puncture_mismatch == 0 && e.puncture_depth <= 1e-3 &&
                  e.prostate_rms <= 0.5e-3 && e.target <= 0.5e-3 && e.volume <= 1e-9;
  std::printf("budget: %s\n", ok ? "held" : "NOT held");
  return ok ? 0 : 1;
}

}  // namespace ps::bench
