#include "engine/tools/probe.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/filling.h"

namespace ps {
namespace {

std::string scene_path() { return std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml"; }

TEST(ProbeScratch, Info) {
  const ScenarioSpec spec = parse_scenario_file(scene_path());
  auto m = compile_scenario(spec);
  std::printf("particles %d substeps %d stable %g\n", m->particle_count(), m->substeps, m->stable_dt_estimate);
  for (auto& c : m->components) std::printf("  %s %d\n", c.name.c_str(), c.particle_count);
  Simulation sim(m);
  sim.add_tool(make_probe_tool(spec, *m));
  auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim.tick());
  double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("100 ticks %.3f s\n", w);
}

}  // namespace
}  // namespace ps
