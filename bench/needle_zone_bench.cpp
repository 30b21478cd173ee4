// Cost of the needle's per-substep work (zone update: tube walk, puncture, cutting and friction
// zones; then the eq. 5/6 forces, stick/slip and the needle's motion: NeedleTool::forces, plus
// NeedleTool::after_step) against the size of the scene (issue 4, item 2). The same 18G needle
// at the same depth (20 mm, inserted at 20 mm/s, then held 0.2 s) in liver-like blocks 40 mm
// deep at 4 mm spacing whose width grows: ~1.1k, ~8k and ~30k particles. Each block has the
// same lattice around the needle, so what the needle meets is the same; only the rest of the
// scene grows. One substep is one tick here (dt 1 ms, 1 substep).
//   BM_NeedleHooks/N   the needle hooks alone on the settled state (the state is not advanced:
//                      every iteration redoes the same incremental zone rebuild). Counters:
//                      visited = particles whose position the zone update tested per substep,
//                      tracked = particles in the needle's tube, particles = scene size.
//   BM_NeedleStep/N    the whole Simulation::step with the needle, for contrast: it grows with N.
// Reproduce: ./build/bench/prostatesim_bench --benchmark_filter='BM_Needle' \
//              --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Measured (medians of 5, CPU time, shared 2-core machine): hooks 4.62 / 4.82 / 4.77 us per
// substep for 1100 / 8019 / 29744 particles, 272 / 272 / 274 particles visited; the whole step
// 92 / 739 / 2796 us.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/simulation.h"
#include "engine/tools/needle/needle.h"

namespace ps::bench {
namespace {

// Block [-w, w]^2 x [-40, 0] mm, 4 mm lattice, bottom held, side faces on frictionless walls
// (as config/validation/needle_liver.yaml), one needle at the centre (off the lattice).
std::string needle_block(int half_width_mm) {
  const std::string w = std::to_string(half_width_mm), w1 = std::to_string(half_width_mm + 1),
                    wm = std::to_string(half_width_mm - 1);
  return "name: bench_needle_block\n"
         "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
         "gravity_m_s2: [0, 0, 0]\n"
         "materials:\n"
         "  liver: {young_kpa: 2.7, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.5, k_f_n: 0.025}\n"
         "components:\n"
         "  - {name: liver, material: liver, spacing_mm: 4, box: {min_mm: [-" + w + ", -" + w + ", -40], max_mm: [" + w + ", " + w +
         ", 0]}}\n"
         "constraints:\n"
         "  - fix: {component: liver, region: {box: {min_mm: [-1000, -1000, -41], max_mm: [1000, 1000, -39]}}}\n"
         "  - fix: {component: liver, axes: x, region: {box: {min_mm: [-" + w1 + ", -" + w1 + ", -41], max_mm: [-" + wm + ", " + w1 + ", 1]}}}\n"
         "  - fix: {component: liver, axes: x, region: {box: {min_mm: [" + wm + ", -" + w1 + ", -41], max_mm: [" + w1 + ", " + w1 + ", 1]}}}\n"
         "  - fix: {component: liver, axes: y, region: {box: {min_mm: [-" + w1 + ", -" + w1 + ", -41], max_mm: [" + w1 + ", -" + wm + ", 1]}}}\n"
         "  - fix: {component: liver, axes: y, region: {box: {min_mm: [-" + w1 + ", " + wm + ", -41], max_mm: [" + w1 + ", " + w1 + ", 1]}}}\n"
         "needles:\n"
         "  puncture_n: {liver: 2.45}\n"
         "  instruments:\n"
         "    - {name: n, gauge: 18, length_mm: 150, start_mm: [1.3, 0.9, 1], direction: [0, 0, -1], "
         "script: [[0, 0], [1.0, 20]]}\n";
}

struct NeedleRun {
  std::shared_ptr<const Model> model;
  std::unique_ptr<Simulation> sim;
  NeedleTool* tool = nullptr;
  State settled;
  bool ok = true;
};

// Built and advanced once per scene size and process (the 30k block takes a few seconds).
NeedleRun& needle_run(int half_width_mm) {
  static std::map<int, std::unique_ptr<NeedleRun>> cache;
  auto& r = cache[half_width_mm];
  if (!r) {
    r = std::make_unique<NeedleRun>();
    const ScenarioSpec spec = parse_scenario_text(needle_block(half_width_mm), "bench_needle.yaml");
    r->model = compile_scenario(spec);
    r->sim = std::make_unique<Simulation>(r->model);
    auto tool = make_needle_tool(r->model, spec.needles);
    r->tool = tool.get();
    r->sim->add_tool(std::move(tool));
    for (int i = 0; i < 1200 && r->ok; ++i) r->ok = r->sim->tick();  // 20 mm deep, then held 0.2 s
    r->settled = r->sim->state();
  }
  return *r;
}

// half widths 18, 52, 102 mm: 10^2, 27^2, 52^2 columns x 11 layers
constexpr int kWidths[] = {18, 52, 102};

void BM_NeedleHooks(benchmark::State& state) {
  NeedleRun& r = needle_run(static_cast<int>(state.range(0)));
  if (!r.ok || r.tool->readout(0).depth < 15e-3) {
    state.SkipWithError("needle scene faulted or the needle is not in the tissue");
    return;
  }
  const Model& m = *r.model;
  State s = r.settled;  // private copy: the hooks add forces to s.f and move the needle
  const double h = m.dt / m.substeps;
  int64_t visited = 0, tracked = 0;
  for (auto _ : state) {
    r.tool->forces(m, s, h);
    r.tool->after_step(m, s, h);
    visited += r.tool->stats(0).visited;
    tracked += r.tool->stats(0).tracked;
    benchmark::DoNotOptimize(s.f.data());
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["particles"] = m.particle_count();
  state.counters["visited"] = static_cast<double>(visited) / it;
  state.counters["tracked"] = static_cast<double>(tracked) / it;
  state.counters["depth_mm"] = 1e3 * r.tool->readout(0).depth;
}

void BM_NeedleStep(benchmark::State& state) {
  NeedleRun& r = needle_run(static_cast<int>(state.range(0)));
  if (!r.ok) {
    state.SkipWithError("needle scene faulted");
    return;
  }
  Simulation& sim = *r.sim;
  sim.state() = r.settled;
  const double h = r.model->dt / r.model->substeps;
  int since = 0;
  for (auto _ : state) {
    if (++since > 200) { sim.state() = r.settled; since = 1; }  // needle held: the scene stays put
    if (!sim.step(h)) { state.SkipWithError("step faulted"); break; }
  }
  state.counters["particles"] = r.model->particle_count();
}

BENCHMARK(BM_NeedleHooks)->Arg(kWidths[0])->Arg(kWidths[1])->Arg(kWidths[2])->Unit(benchmark::kNanosecond);
BENCHMARK(BM_NeedleStep)->Arg(kWidths[0])->Arg(kWidths[1])->Arg(kWidths[2])->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ps::bench
