// Issue 2's long-run robustness test: the default scene (config/biopsy.yaml, unchanged, with the
// instruments `prostatesim simulate` adds) runs 100 000 substeps without a fault. The step's own
// check rejects NaN/Inf, a particle faster than the speed limit or farther than the excursion
// limit, so "no fault" means no NaN and no blow-up; the test also checks the final state is
// finite and the volume-constrained organs are held. About 2 minutes on one core (~1.2 ms per
// substep, docs/performance.md); `prostatesim_bench --soak N` runs the same scene by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/run.h"
#include "engine/sim/scene.h"
#include "engine/step/simulation.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"

namespace ps {
namespace {

TEST(DefaultScene, NoNaNOrBlowUpOver100kSubsteps) {
  Scene scene = load_scene(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
  const auto model = scene.model;
  Simulation& sim = *scene.sim;
  ASSERT_FALSE(sim.tools().empty()) << "the default scene should carry its instruments";

  constexpr int64_t kSubsteps = 100000;
  const int64_t ticks = (kSubsteps + model->substeps - 1) / model->substeps;
  RunOptions opt;
  opt.duration = static_cast<double>(ticks) * model->dt;
  const RunResult r = run_simulation(sim, opt);
  ASSERT_FALSE(r.faulted) << r.fault;
  EXPECT_GE(r.steps, kSubsteps);
  for (size_t p = 0; p < sim.state().x.size(); ++p) {
    ASSERT_TRUE(sim.state().x[p].allFinite()) << "particle " << p;
    ASSERT_TRUE(sim.state().v[p].allFinite()) << "particle " << p;
  }
  for (const Surface& surf : model->surfaces) {
    if (!surf.volume_constrained) continue;
    const std::string& name = model->components[surf.component].name;
    EXPECT_LE(r.volume_error.at(name), 1e-9) << name;
  }
  std::printf("default scene: %lld substeps (%.3f s simulated), %.1f s wall, kinetic energy %.3g J\n",
              static_cast<long long>(r.steps), r.sim_time, r.wall_time, r.kinetic_energy);
}

}  // namespace
}  // namespace ps
