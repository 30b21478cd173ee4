// Single stages on a warmed (deformed) state, repeated: the shape-memory stage (optimised and the
// pre-optimisation reference copy, same binary, so their ratio is the speed-up; also its
// x86-64-baseline build, which CPUs without AVX run) and the check.
// Both only read positions, so repeating them keeps the state representative.
#include <benchmark/benchmark.h>

#include "bench/bench_common.h"
#include "bench/bench_modes.h"
#include "engine/step/stages.h"

namespace ps::bench {
namespace {

void per_particle(benchmark::State& state, int n) {
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["per_particle"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate |
                                                             benchmark::Counter::kInvert);
}

template <void (*Fn)(const Model&, State&)>
void BM_ShapeMemoryImpl(benchmark::State& state, const char* scene) {
  auto sim = warmed(scene);
  const Model& m = sim->model();
  State& s = sim->state();
  for (auto _ : state) {
    Fn(m, s);  // accumulates into s.f; positions untouched
    benchmark::ClobberMemory();
  }
  per_particle(state, m.particle_count());
}

void BM_Check(benchmark::State& state, const char* scene) {
  auto sim = warmed(scene);
  for (auto _ : state) benchmark::DoNotOptimize(check_state(sim->model(), sim->state()));
  per_particle(state, sim->model().particle_count());
}

constexpr auto kOpt = BM_ShapeMemoryImpl<add_shape_memory_forces>;
constexpr auto kRef = BM_ShapeMemoryImpl<reference_add_shape_memory_forces>;
constexpr auto kBase = BM_ShapeMemoryImpl<detail::add_shape_memory_forces_baseline>;

BENCHMARK_CAPTURE(kOpt, cube11, "cube11")->Name("BM_ShapeMemory/cube11")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kRef, cube11, "cube11")->Name("BM_ShapeMemoryReference/cube11")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kOpt, cube22, "cube22")->Name("BM_ShapeMemory/cube22")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kRef, cube22, "cube22")->Name("BM_ShapeMemoryReference/cube22")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kBase, cube11, "cube11")->Name("BM_ShapeMemoryBaselineBuild/cube11")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kBase, cyl, "cyl")->Name("BM_ShapeMemoryBaselineBuild/cyl")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kOpt, cyl, "cyl")->Name("BM_ShapeMemory/cyl")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kRef, cyl, "cyl")->Name("BM_ShapeMemoryReference/cyl")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kOpt, biopsy, "biopsy")->Name("BM_ShapeMemory/biopsy")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kRef, biopsy, "biopsy")->Name("BM_ShapeMemoryReference/biopsy")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Check, cube11, "cube11")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ps::bench
