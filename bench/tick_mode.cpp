// `prostatesim_bench --ticks SCENARIO N`: N ticks of a scenario file with its instruments (needles,
// probe, filling, added in build_scene's order) after 20 warm-up ticks. Under
// valgrind --tool=callgrind --collect-atstart=no only those N ticks are counted: the per-tick
// instruction count of a default scene with its tools (docs/performance.md), e.g. to check that
// a change to the engine's seams leaves it unchanged. Plain make_*_tool calls (no build_scene) so
// the same file builds on older trees for a before/after comparison.
#include <cstdio>

#include "bench/bench_modes.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/tool_kind.h"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define PS_CALLGRIND_TOGGLE() CALLGRIND_TOGGLE_COLLECT
#else
#define PS_CALLGRIND_TOGGLE() ((void)0)
#endif

namespace ps::bench {

int run_ticks(const std::string& file, int ticks) {
  const ScenarioSpec spec = parse_scenario_file(file);
  auto model = compile_scenario(spec);
  Simulation sim(model);
  add_scenario_tools(spec, model, sim);  // every kind the scenario has, connected as build_scene does
  for (int i = 0; i < 20; ++i) sim.tick();
  PS_CALLGRIND_TOGGLE();
  bool ok = true;
  for (int i = 0; i < ticks && ok; ++i) ok = sim.tick();
  PS_CALLGRIND_TOGGLE();
  if (!ok) {
    std::fprintf(stderr, "%s\n", sim.state().fault.describe(*model).c_str());
    return 1;
  }
  std::printf("%s: %d ticks of %d substeps, %zu tools, hash_state %016llx\n", file.c_str(), ticks, model->substeps, sim.tools().size(),
              static_cast<unsigned long long>(hash_state(sim.state())));
  if (model->sleep.enabled()) {
    int asleep = 0;
    for (uint8_t a : sim.state().asleep) asleep += a;
    std::printf("sleeping: %d of %d particles that may sleep; %d of %d tet elements evaluated\n", asleep,
                model->sleep.eligible_count, sim.state().tet_awake_count, model->tets.count());
  }
  return 0;
}

}  // namespace ps::bench
