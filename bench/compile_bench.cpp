// How long a default scene takes to compile (parse + compile_scenario: particles, neighbours,
// Delaunay elements, materials, constraints, tools' data): what a trainee waits for at start-up
// and an instructor after each edit in the editor. One iteration is one parse and compile.
//   prostatesim_bench --benchmark_filter=BM_CompileScenario --benchmark_repetitions=3
// (Formerly a CPU-time bound in the unit tests, which failed under sanitizers and on a busy host.)
#include <benchmark/benchmark.h>

#include <string>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"

namespace ps {
namespace {

const char* const kScenes[] = {"biopsy", "brachytherapy", "bladder_filling"};

void BM_CompileScenario(benchmark::State& state) {
  const std::string name = kScenes[state.range(0)];
  const std::string file = std::string(PROSTATESIM_SOURCE_DIR) + "/config/" + name + ".yaml";
  int particles = 0, elements = 0;
  for (auto _ : state) {
    const auto model = compile_scenario(parse_scenario_file(file));
    particles = model->particle_count();
    elements = model->tets.count();
    benchmark::DoNotOptimize(model.get());
  }
  state.SetLabel(name);
  state.counters["particles"] = particles;
  state.counters["elements"] = elements;
}
BENCHMARK(BM_CompileScenario)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ps
