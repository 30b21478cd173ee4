// `prostatesim_bench --tick-trace SCENARIO SCRIPT [WINDOW_MS]`: runs a scenario file with its
// script once (as `prostatesim run` builds it, lockstep, no pacing) and prints, per window of
// simulated time (default 250 ms), this thread's CPU time per tick: mean, p99 and max, and every
// stage that took part of it, the largest first. It finds the phases of a script (needles deep, a puncture,
// a seed drop) that set the real-time loop's p99, which a whole-run profile averages away.
// CPU time, not wall time, so a shared machine's other tenants blur it less.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bench/bench_modes.h"
#include "engine/realtime/lockstep.h"
#include "engine/realtime/physics_loop.h"
#include "engine/realtime/script.h"
#include "engine/realtime/scripted_run.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"
#include "engine/util/thread_cpu_time.h"

namespace ps::bench {
namespace {

// CPU time per pipeline stage, summed until reset
class StageCpu final : public StageProbe {
 public:
  void begin(int) override { t0_ = thread_cpu_ns(); }
  void end(int stage) override { ns[stage] += thread_cpu_ns() - t0_; }
  int64_t ns[kStageCount] = {};

 private:
  int64_t t0_ = 0;
};

}  // namespace

int tick_trace(const std::string& file, const std::string& script_file, double window_ms) {
  ScriptedRun sr(parse_scenario_file(file), script_file);
  const Scene& sc = sr.sc;
  LockstepRunner& run = sr.run;
  const Model& m = *sc.model;
  const int64_t ticks = sr.ticks();
  const int64_t window = std::max<int64_t>(1, std::llround(window_ms * 1e-3 / m.dt));
  std::printf("%s, %s: %d particles, tick %.3g ms x %d substeps, %lld ticks, windows of %lld ticks\n", file.c_str(),
              script_file.c_str(), m.particle_count(), m.dt * 1e3, m.substeps, static_cast<long long>(ticks),
              static_cast<long long>(window));
  std::printf("%9s %9s %9s %9s  %s\n", "t_end[s]", "mean[ms]", "p99[ms]", "max[ms]", "stages [ms/tick], the largest first");
  StageCpu probe;
  std::vector<double> win, all;
  win.reserve(static_cast<size_t>(window));
  all.reserve(static_cast<size_t>(ticks));
  for (int64_t k = 0; k < ticks; ++k) {
    const int64_t t0 = thread_cpu_ns();
    if (!run.runner().step(&probe)) {
      std::printf("fault: %s\n", run.runner().fault_text().c_str());
      return 1;
    }
    const double ms = (thread_cpu_ns() - t0) * 1e-6;
    win.push_back(ms);
    all.push_back(ms);
    if (static_cast<int64_t>(win.size()) == window || k + 1 == ticks) {
      double sum = 0.0;
      for (double w : win) sum += w;
      std::vector<double> sorted = win;
      std::sort(sorted.begin(), sorted.end());
      const double p99 = sorted[std::min(sorted.size() - 1, static_cast<size_t>(0.99 * sorted.size()))];
      std::printf("%9.3f %9.3f %9.3f %9.3f ", sc.sim->state().time, sum / win.size(), p99, sorted.back());
      int order[kStageCount];
      for (int i = 0; i < kStageCount; ++i) order[i] = i;
      std::sort(order, order + kStageCount, [&](int a, int b) { return probe.ns[a] > probe.ns[b]; });
      for (int i = 0; i < kStageCount && probe.ns[order[i]] > 0; ++i)
        std::printf(" %s %.3f", stage_name(static_cast<Stage>(order[i])), probe.ns[order[i]] * 1e-6 / win.size());
      std::printf("\n");
      std::fill(probe.ns, probe.ns + kStageCount, 0);
      win.clear();
    }
  }
  // the same ticks taken two at a time, as a 500 Hz loop of 1 ms ticks runs them (time.loop_ticks)
  std::vector<double> pairs;
  for (size_t k = 0; k + 1 < all.size(); k += 2) pairs.push_back(all[k] + all[k + 1]);
  std::sort(pairs.begin(), pairs.end());
  std::sort(all.begin(), all.end());
  double sum = 0.0;
  for (double a : all) sum += a;
  std::printf("whole run: mean %.3f ms, p50 %.3f, p99 %.3f, max %.3f ms of CPU per tick\n", sum / all.size(),
              all[all.size() / 2], all[std::min(all.size() - 1, static_cast<size_t>(0.99 * all.size()))], all.back());
  if (!pairs.empty())
    std::printf("two ticks at a time: p50 %.3f, p99 %.3f, max %.3f ms of CPU per pair\n", pairs[pairs.size() / 2],
                pairs[std::min(pairs.size() - 1, static_cast<size_t>(0.99 * pairs.size()))], pairs.back());
  return 0;
}

}  // namespace ps::bench
