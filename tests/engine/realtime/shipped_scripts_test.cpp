// The shipped scripts (config/scripts/biopsy.yaml, brachytherapy.yaml) drive their default scenes
// to the end headless without a fault, a watchdog finding or a refused command, and do what they
// say: the biopsy takes its core, the brachytherapy pull-back drops all four seeds. CI-short: the
// scenes are built from the shipped files with every component but the prostate 1.6x coarser
// (link distances with them; the same prostate, instruments, script, tick and substeps). The full-resolution runs are
// `prostatesim run config/<scene>.yaml --script config/scripts/<scene>.yaml --headless --unpaced`
// (docs/realtime.md has their figures).
#include <gtest/gtest.h>

#include <cstdlib>

#include "engine/realtime/lockstep.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/watchdog.h"
#include "engine/tools/needle/needle.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

struct Outcome {
  int64_t ticks = 0, end_tick = 0;
  double dt = 0.0;  // the scene's tick [s]
  int64_t applied = 0, refused = 0, commands = 0;
  int cores = 0, seeds = 0, punctures = 0;
  std::string fault;
};

bool slow_tests() {
  const char* e = std::getenv("PROSTATESIM_SLOW_TESTS");
  return e && *e && std::string(e) != "0";
}

Outcome run_shipped(const std::string& scene_file, const std::string& script_file) {
  const std::string dir = std::string(PROSTATESIM_SOURCE_DIR) + "/config/";
  Scene sc = load_scene(dir + scene_file);
  const Script s = parse_script_file(dir + "scripts/" + script_file);
  std::vector<Command> cmds = script_commands(s, sc);
  Outcome o;
  o.commands = static_cast<int64_t>(cmds.size());
  CommandPlayer player(std::move(cmds));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  const Watchdog dog(*sc.model);
  run.runner().set_watchdog(&dog);
  o.dt = sc.model->dt;
  o.end_tick = static_cast<int64_t>(std::llround(s.duration / sc.model->dt));
  while (run.tick() < o.end_tick) {
    if (!run.advance_to(std::min(o.end_tick, run.tick() + 250))) break;
    for (const SnapshotEvent& e : run.snapshot().events) {
      o.cores += e.kind == static_cast<uint8_t>(NeedleEventKind::Core);
      o.seeds += e.kind == static_cast<uint8_t>(NeedleEventKind::Seed);
      o.punctures += e.kind == static_cast<uint8_t>(NeedleEventKind::Puncture);
    }
  }
  o.ticks = run.tick();
  o.fault = run.runner().fault_text();
  o.applied = run.applier().applied();
  o.refused = run.applier().refused();
  for (int i = 0; i < run.applier().refusals().size(); ++i) ADD_FAILURE() << run.applier().refusals().at(i).describe();
  std::printf("%s + scripts/%s (%d particles): %lld ticks, %lld commands, %d punctures, %d cores, %d seeds\n",
              scene_file.c_str(), script_file.c_str(), sc.model->particle_count(), static_cast<long long>(o.ticks),
              static_cast<long long>(o.applied), o.punctures, o.cores, o.seeds);
  return o;
}

TEST(ShippedScripts, BiopsyRunsToTheEndAndTakesItsCore) {
  if (!slow_tests()) GTEST_SKIP() << "minutes: set PROSTATESIM_SLOW_TESTS=1";
  const Outcome o = run_shipped("biopsy.yaml", "biopsy.yaml");
  EXPECT_EQ(o.fault, "");
  EXPECT_EQ(o.ticks, o.end_tick);
  EXPECT_NEAR(o.end_tick * o.dt, 3.0, 1e-9);  // the script's 3 s
  EXPECT_EQ(o.refused, 0);
  EXPECT_EQ(o.applied, o.commands);
  EXPECT_GE(o.punctures, 1);
  EXPECT_EQ(o.cores, 1);
}

TEST(ShippedScripts, BrachytherapyRunsToTheEndAndDropsEverySeed) {
  if (!slow_tests()) GTEST_SKIP() << "minutes: set PROSTATESIM_SLOW_TESTS=1";
  const Outcome o = run_shipped("brachytherapy.yaml", "brachytherapy.yaml");
  EXPECT_EQ(o.fault, "");
  EXPECT_EQ(o.ticks, o.end_tick);
  EXPECT_NEAR(o.end_tick * o.dt, 6.5, 1e-9);  // the script's 6.5 s
  EXPECT_EQ(o.refused, 0);
  EXPECT_EQ(o.applied, o.commands);
  EXPECT_GE(o.punctures, 1);
  EXPECT_EQ(o.seeds, 4);
}

}  // namespace
}  // namespace ps
