// Issue 14 "skip what a scene doesn't need": a stage a scene does not use is not in its pipeline
// (Simulation::build_pipeline), so it costs nothing. Measured here on the 1331-particle cube:
//   BM_PipelineStep/bare       the cube as it is: no tool, rigid body, volume or strain stage;
//   BM_PipelineStep/idle_tool  the same cube with a Tool whose hooks do nothing: the four tool
//                              stages are now present, and the difference to `bare` is what they
//                              would cost if every scene carried them;
//   BM_PipelineStep/volume     the cube incompressible (the Volume stage does work).
// Counter `stages` is the pipeline length. Run: prostatesim_bench --benchmark_filter=Pipeline
#include <benchmark/benchmark.h>

#include "bench/bench_common.h"

namespace ps::bench {
namespace {

class IdleTool : public Tool {
 public:
  const char* name() const override { return "idle"; }
  void boundary_conditions(const Model&, State&, double) override { benchmark::ClobberMemory(); }
  void forces(const Model&, State&, double) override { benchmark::ClobberMemory(); }
  void constraints(const Model&, State&, double) override { benchmark::ClobberMemory(); }
  void after_step(const Model&, State&, double) override { benchmark::ClobberMemory(); }
};

void BM_PipelineStep(benchmark::State& state, const char* scene, bool idle_tool) {
  CyclingRun run(scene);
  if (idle_tool) run.sim().add_tool(std::make_unique<IdleTool>());
  for (auto _ : state) {
    run.maybe_restore();
    benchmark::DoNotOptimize(run.sim().step(run.h()));
  }
  state.counters["stages"] = static_cast<double>(run.sim().pipeline().size());
  state.counters["particles"] = run.sim().model().particle_count();
}

BENCHMARK_CAPTURE(BM_PipelineStep, bare, "cube11", false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_PipelineStep, idle_tool, "cube11", true)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_PipelineStep, volume, "cube11i", false)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ps::bench
