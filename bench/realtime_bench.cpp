// Realtime factor and tick time of the default scenes with a needle inserting and the probe in
// place (bench/realtime_scenes.h), physics alone, one thread. One benchmark iteration is one
// tick (model.dt, all its substeps). The scene is first advanced to the warm-up time (biopsy
// 0.1 s: the needle is moving; brachytherapy 0.4 s: its needles entered the perineum), then
// kTicks ticks are timed one by one. Counters:
//   realtime_wall  simulated seconds per wall second over the timed ticks
//   realtime_cpu   same per CPU second of this thread (the figure a shared machine does not blur)
//   tick_p50_us, tick_p99_us   median and 99th percentile of the wall time of one tick
//   tick_period_us             the tick (model.dt) for comparison with p99
//   substeps, particles
// Arguments: triplets per particle (0: all, the paper's scheme), substeps per tick (0: the file's),
// solver.mass_scaling (-1: the file's, 0 off, 1 on).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <vector>

#include "bench/realtime_scenes.h"
#include "engine/scenario/compile.h"
#include "engine/sim/scene.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/util/thread_cpu_time.h"
#include "engine/tools/tool_kind.h"

namespace ps::bench {
namespace {

constexpr int kTicks = 300;

void BM_Realtime(benchmark::State& state, const char* scene) {
  const ScenarioSpec spec = realtime_scene(scene, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                                            static_cast<int>(state.range(2)));
  auto model = compile_scenario(spec);
  Simulation sim(model);
  add_scenario_tools(spec, model, sim);  // every kind the scenario has, connected as build_scene does
  const double warm = std::string(scene) == "biopsy" ? 0.1 : 0.4;
  while (sim.state().time < warm - 0.5 * model->dt)
    if (!sim.tick()) { state.SkipWithError("warm-up faulted"); return; }
  std::vector<double> tick_s;
  tick_s.reserve(kTicks);
  double cpu = 0.0;
  for (auto _ : state) {
    const int64_t c0 = thread_cpu_ns();
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = sim.tick();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cpu += (thread_cpu_ns() - c0) * 1e-9;
    state.SetIterationTime(wall);
    tick_s.push_back(wall);
    if (!ok) { state.SkipWithError("tick faulted"); break; }
  }
  if (tick_s.empty()) return;
  double wall_sum = 0.0;
  for (double t : tick_s) wall_sum += t;
  std::sort(tick_s.begin(), tick_s.end());
  auto pct = [&](double q) { return tick_s[std::min(tick_s.size() - 1, static_cast<size_t>(q * tick_s.size()))]; };
  const double simulated = model->dt * static_cast<double>(tick_s.size());
  state.counters["realtime_wall"] = simulated / wall_sum;
  state.counters["realtime_cpu"] = simulated / cpu;
  state.counters["tick_p50_us"] = 1e6 * pct(0.5);
  state.counters["tick_p99_us"] = 1e6 * pct(0.99);
  state.counters["tick_period_us"] = 1e6 * model->dt;
  state.counters["substeps"] = model->substeps;
  state.counters["particles"] = model->particle_count();
}

// {triplets, substeps, mass_scaling}: {0, 0, -1} is the scene as shipped (the paper's explicit
// scheme at the compiler's substep); {0, S, 1} solver.mass_scaling at half the file's substeps,
// the setting whose error against the converged reference is measured (docs/performance.md)
BENCHMARK_CAPTURE(BM_Realtime, biopsy, "biopsy")
    ->Args({0, 0, -1})->Args({0, 9, 1})->Iterations(kTicks)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Realtime, brachytherapy, "brachytherapy")
    ->Args({0, 0, -1})->Args({0, 7, 1})->Iterations(kTicks)->UseManualTime()->Unit(benchmark::kMicrosecond);

// What the app adds to each tick on the physics thread: the save of the last good state before
// every tick (TickRunner::keep_last_good, `run` and the window), and a recording's full state hash
// every hash_every (100) ticks (Simulation::hash: the same save, then FNV-1a over its bytes).
// The scene as shipped, with its tools, after 0.1 s.
void BM_StateSave(benchmark::State& state, const char* scene, bool hash) {
  Scene sc = build_scene(realtime_scene(scene));
  Simulation& sim = *sc.sim;
  while (sim.state().time < 0.1 - 0.5 * sc.model->dt)
    if (!sim.tick()) { state.SkipWithError("warm-up faulted"); return; }
  std::vector<uint8_t> buf;
  sim.save(buf);
  uint64_t h = 0;
  for (auto _ : state) {
    if (hash) h ^= sim.hash();
    else sim.save(buf);
    benchmark::DoNotOptimize(buf.data());
  }
  benchmark::DoNotOptimize(h);
  state.counters["bytes"] = static_cast<double>(buf.size());
}
BENCHMARK_CAPTURE(BM_StateSave, biopsy, "biopsy", false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StateSave, brachytherapy, "brachytherapy", false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StateSave, brachytherapy_hash, "brachytherapy", true)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ps::bench
