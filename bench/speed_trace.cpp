// `prostatesim_bench --speed-trace SCENARIO SCRIPT [SUBSTEPS [MASS_SCALING]]`: runs a scenario file
// with its script once (the scene as `prostatesim run` builds it) and prints, per 10 ms window,
// the largest particle speed with its particle and organ and the first needle's tip speed; then
// the run's peak. SUBSTEPS > 0 and MASS_SCALING 0/1 override the file's solver settings, so the
// shipped setting and a converged one (e.g. 12 substeps) can be compared event by event. It is
// how docs/robustness.md tells a physical event (the converged run has
// it too) from a numerical one (it does not).
#include <cmath>
#include <cstdio>

#include "bench/bench_modes.h"
#include "engine/realtime/lockstep.h"
#include "engine/realtime/script.h"
#include "engine/realtime/scripted_run.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"
#include "engine/tools/needle/needle.h"

namespace ps::bench {

int speed_trace(const std::string& file, const std::string& script_file, int substeps, int mass_scaling) {
  ScenarioSpec spec = parse_scenario_file(file);
  if (substeps > 0) spec.substeps = substeps;
  if (mass_scaling >= 0) spec.mass_scaling = mass_scaling != 0;
  ScriptedRun sr(spec, script_file);
  const Scene& sc = sr.sc;
  LockstepRunner& run = sr.run;
  const Model& m = *sc.model;
  const NeedleTool* needles =
      sc.tools.has<NeedleTool>() ? sc.tools.as<NeedleTool>() : nullptr;
  const int64_t ticks = sr.ticks();
  const int64_t window = std::max<int64_t>(1, std::llround(0.01 / m.dt));
  std::printf("%s, %s: %d substeps, mass scaling %s, %lld ticks\n", file.c_str(), script_file.c_str(), m.substeps,
              spec.mass_scaling ? "on" : "off", static_cast<long long>(ticks));
  std::printf("%10s %12s %9s %-12s %14s\n", "t_end[s]", "max_v[m/s]", "particle", "organ", "tip_v[m/s]");
  auto organ = [&](int p) { return p >= 0 ? m.components[m.component_of[p]].name : std::string("-"); };
  double peak = 0.0, peak_t = 0.0, win = 0.0, tip = 0.0;
  int peak_p = -1, win_p = -1;
  for (int64_t k = 0; k < ticks; ++k) {
    if (!run.step()) {
      std::printf("fault: %s\n", run.runner().fault_text().c_str());
      return 1;
    }
    const State& s = sc.sim->state();
    for (int p = 0; p < m.particle_count(); ++p) {
      const double v = s.v[p].norm();
      if (v > win) { win = v; win_p = p; }
      if (v > peak) { peak = v; peak_p = p; peak_t = s.time; }
    }
    if (needles && needles->count() > 0) tip = std::max(tip, needles->readout(0).velocity.norm());
    if ((k + 1) % window == 0 || k + 1 == ticks) {
      std::printf("%10.3f %12.4f %9d %-12s %14.4f\n", s.time, win, win_p, organ(win_p).c_str(), tip);
      win = tip = 0.0;
      win_p = -1;
    }
  }
  std::printf("peak %.4f m/s at t = %.4f s, particle %d (%s)\n", peak, peak_t, peak_p, organ(peak_p).c_str());
  return 0;
}

}  // namespace ps::bench
