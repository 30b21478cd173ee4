// Single stages on a warmed (deformed) state, repeated: the shape-memory stage (optimised and the
// pre-optimisation reference copy, same binary, so their ratio is the speed-up; also its
// x86-64-baseline build, which CPUs without AVX run), the check, and the tet element pass at its
// two vector widths.
// Both only read positions, so repeating them keeps the state representative.
#include <benchmark/benchmark.h>

#include <vector>

#include "bench/bench_common.h"
#include "bench/bench_modes.h"
#include "engine/model/shell_elements.h"
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

// The tet element pass over every element of the warmed biopsy scene at its own node pressures'
// stand-in (1 kPa on every node): four elements per vector against eight (AVX-512; the same bits,
// tests/engine/step/tet_elastic_test.cpp). Skipped where the CPU has no AVX-512.
void BM_TetElementForces(benchmark::State& state) {
  const int lanes = static_cast<int>(state.range(0));
  if (lanes == 8 && !tet_element_forces8_available()) {
    state.SkipWithError("no AVX-512 on this CPU");
    return;
  }
  auto sim = warmed("biopsy");
  const TetElements& te = sim->model().tets;
  State& s = sim->state();
  std::vector<double> p(te.nodes.size(), 1e3);
  for (auto _ : state) {
    if (lanes == 8) tet_element_forces8(te, s.x.data(), p.data(), nullptr, 0, te.count(), 1.0, s.f.data());
    else tet_element_forces4(te, s.x.data(), p.data(), nullptr, 0, te.count(), 1.0, s.f.data());
    benchmark::ClobberMemory();
  }
  state.counters["per_element"] = benchmark::Counter(te.count(), benchmark::Counter::kIsIterationInvariantRate |
                                                                      benchmark::Counter::kInvert);
}
BENCHMARK(BM_TetElementForces)->Arg(4)->Arg(8)->Unit(benchmark::kMicrosecond);

// A range's node volumes then its element forces, as the step runs them, on the warmed biopsy
// scene: the force pass gathering the positions again (arg 0) against reading the edges the
// volume pass kept (arg 1; State::tet_edges, the same bits); range 0 all elements, 1 the fast
// group, 2 the slow group (multi-rate).
void BM_TetRangePass(benchmark::State& state) {
  const bool edges = state.range(0) != 0;
  const int range = static_cast<int>(state.range(1));
  auto sim = warmed("biopsy");
  const TetElements& te = sim->model().tets;
  State& s = sim->state();
  const int nt = te.count(), nf = te.fast_count;
  const int begin = range == 2 ? nf : 0, end = range == 1 ? nf : nt;
  std::vector<double> p(te.nodes.size(), 0.0);
  for (auto _ : state) {
    for (double& v : p) v = 0.0;
    const bool kept = add_tet_range_volumes(te, s.x.data(), begin, end, s.tet_quarter.data(), p.data(), edges ? s.tet_edges.data() : nullptr);
    tet_node_pressures(te, p.data());
    tet_element_forces(te, s.x.data(), p.data(), nullptr, begin, end, 1.0, s.f.data(), kept ? s.tet_edges.data() : nullptr);
    benchmark::ClobberMemory();
  }
  state.counters["per_element"] = benchmark::Counter(end - begin, benchmark::Counter::kIsIterationInvariantRate |
                                                                       benchmark::Counter::kInvert);
}
BENCHMARK(BM_TetRangePass)->ArgsProduct({{0, 1}, {0, 1, 2}})->Unit(benchmark::kMicrosecond);

// The shell walls' passes over the warmed biopsy scene's bladder and rectum (arg 0 membranes,
// 1 hinges), as the step runs them: blocks of lanes, the same bits as the scalar pass
// (tests/engine/step/shell_elastic_test.cpp).
void BM_ShellForces(benchmark::State& state) {
  const bool hinges = state.range(0) != 0;
  auto sim = warmed("biopsy");
  const ShellElements& sh = sim->model().shells;
  State& s = sim->state();
  const int n = hinges ? sh.hinge_count() : sh.triangle_count();
  for (auto _ : state) {
    if (hinges) add_shell_hinge_forces(sh, s.x.data(), 0, n, s.f.data());
    else add_shell_membrane_forces(sh, s.x.data(), 0, n, s.f.data());
    benchmark::ClobberMemory();
  }
  state.counters["per_element"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ShellForces)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

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
