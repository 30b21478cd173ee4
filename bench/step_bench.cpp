// One physics substep, Simulation::step(), single thread. items_per_second counts particles, so
// 1/items_per_second is the time per particle-iteration; ns_per_particle shows it directly.
// BM_StepStages runs the same pipeline stage by stage (bench/modes.cpp timed_step) and reports the
// mean wall time of each stage per step in ns (clock reads add ~20 ns per stage) and its share
// of the step in percent. Every benchmark restores its warmed state every kCycle substeps
// (bench_common.h).
#include <benchmark/benchmark.h>

#include "bench/bench_common.h"
#include "bench/bench_modes.h"

namespace ps::bench {
namespace {

void set_particle_counters(benchmark::State& state, int n) {
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["particles"] = n;
  // seconds per particle-iteration (printed with an SI prefix: "40n" = 40 ns)
  state.counters["per_particle"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate |
                                                             benchmark::Counter::kInvert);
}

void BM_Step(benchmark::State& state, const char* scene) {
  CyclingRun run(scene);
  Simulation& sim = run.sim();
  const double h = run.h();
  for (auto _ : state) {
    run.maybe_restore();
    if (!sim.step(h)) { state.SkipWithError("step faulted"); break; }
  }
  set_particle_counters(state, sim.model().particle_count());
}

void BM_StepStages(benchmark::State& state, const char* scene) {
  CyclingRun run(scene);
  Simulation& sim = run.sim();
  StageTimes times;
  for (auto _ : state) {
    run.maybe_restore();
    if (!timed_step(sim, run.h(), times)) { state.SkipWithError("step faulted"); break; }
  }
  set_particle_counters(state, sim.model().particle_count());
  // wall time per stage and its share of the step: on a shared machine preemption lands in the
  // stages in proportion to their length, so the shares are the robust figure
  int64_t total = 0;
  for (Stage st : sim.pipeline()) total += times.ns[static_cast<int>(st)];
  for (Stage st : sim.pipeline()) {
    const double ns = static_cast<double>(times.ns[static_cast<int>(st)]);
    state.counters[std::string(stage_name(st)) + "_ns"] = benchmark::Counter(ns, benchmark::Counter::kAvgIterations);
    state.counters[std::string(stage_name(st)) + "_pct"] = total > 0 ? 100.0 * ns / static_cast<double>(total) : 0.0;
  }
}

BENCHMARK_CAPTURE(BM_Step, cube11, "cube11")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, cube11i, "cube11i")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, cube11s, "cube11s")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, cube11si, "cube11si")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, cube22, "cube22")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, cube22i, "cube22i")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, cyl, "cyl")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, cyli, "cyli")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Step, biopsy, "biopsy")->Unit(benchmark::kMicrosecond);

BENCHMARK_CAPTURE(BM_StepStages, cube11, "cube11")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StepStages, cube11i, "cube11i")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StepStages, cube11si, "cube11si")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StepStages, cube22i, "cube22i")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StepStages, cyli, "cyli")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StepStages, biopsy, "biopsy")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ps::bench
