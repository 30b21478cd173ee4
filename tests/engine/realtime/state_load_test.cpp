// Loading a saved state in the live path (engine/realtime/tick_runner.h load_state,
// physics_loop.h load_state, state_file.h check_state_matches): a state saved at tick 150 of the
// live scene's script, through a file, loaded into a fresh scene (lock-step and the threaded loop
// while it runs) goes on to the very bits of a run that never stopped; a file of another
// scenario, a damaged one or one whose bytes do not fit are refused naming the file and the field,
// with the runner and the simulation unchanged.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include <unistd.h>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/physics_loop.h"
#include "engine/realtime/state_file.h"
#include "engine/util/error.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

struct LiveRun {
  Scene sc = test::make_live_scene();
  Script script = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player{script_commands(script, sc)};
  LockstepRunner run{*sc.sim};
  LiveRun() { run.add_source(&player); }
};

std::string temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("prostatesim_state_load_" + name + "_" + std::to_string(::getpid()))).string();
}

// the state after 150 ticks, written to a file as `run` writes it, read back
SavedState saved_at_150(const std::string& path) {
  LiveRun a;
  EXPECT_TRUE(a.run.advance_to(150));
  SavedState st;
  a.run.runner().current_state(st);
  st.scenario = a.sc.spec.name;
  st.scenario_hash = 0x1234;
  write_state_file(path, st);
  return read_state_file(path);
}

TEST(StateLoad, SavedAtTick150LoadedIntoAFreshSceneGoesOnBitForBit) {
  LiveRun clean;
  ASSERT_TRUE(clean.run.advance_to(150));
  const uint64_t at150 = clean.run.hash();
  ASSERT_TRUE(clean.run.advance_to(450));
  const uint64_t at450 = clean.run.hash();

  const std::string path = temp("ok");
  const SavedState st = saved_at_150(path);
  EXPECT_EQ(st.tick, 150);
  EXPECT_EQ(st.state_hash, at150);
  EXPECT_EQ(st.file, path);
  check_state_matches(st, "live_box", 0x1234);  // no throw

  LiveRun b;
  ASSERT_TRUE(b.run.advance_to(40));  // mid-run: the load replaces this
  b.run.runner().load_state(st);
  EXPECT_EQ(b.run.tick(), 150);
  EXPECT_EQ(b.run.hash(), at150);
  EXPECT_NEAR(b.sc.sim->state().time, 0.15, 1e-12);
  ASSERT_TRUE(b.run.advance_to(450)) << b.run.runner().fault_text();
  EXPECT_EQ(b.run.hash(), at450) << "the script's commands from tick 150 on were not applied as in the clean run";
  std::filesystem::remove(path);
}

TEST(StateLoad, TheThreadedLoopLoadsBetweenTicksWhileItRuns) {
  LiveRun clean;
  ASSERT_TRUE(clean.run.advance_to(450));
  const uint64_t at450 = clean.run.hash();
  const std::string path = temp("loop");
  const SavedState st = saved_at_150(path);

  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  LoopOptions o;
  o.log_timing = false;
  o.factor = 0.25;  // slow: still running when the load arrives
  o.stop_at_tick = 450;
  PhysicsLoop loop(*sc.sim, o);
  loop.add_source(&player);
  loop.keep_last_good(true);
  loop.start();
  loop.wait_for_tick(20);
  loop.load_state(st);  // the UI thread waits, the physics loads it between two ticks
  EXPECT_GE(loop.tick(), 150);
  loop.set_factor(100.0);
  loop.wait_for_tick(450);
  for (int i = 0; i < 5000 && !loop.paused(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  loop.stop();
  EXPECT_FALSE(loop.faulted()) << loop.fault_text();
  EXPECT_EQ(loop.tick(), 450);
  EXPECT_EQ(sc.sim->hash(), at450);
  std::filesystem::remove(path);
}

TEST(StateLoad, BadFilesAreRefusedNamingFileAndFieldAndNothingChanges) {
  const std::string path = temp("bad");
  SavedState st = saved_at_150(path);
  // another scenario
  try {
    check_state_matches(st, "biopsy", 0x1234);
    ADD_FAILURE() << "a state of another scenario was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.field(), "scenario");
    EXPECT_EQ(e.line(), 3);
  }
  try {
    check_state_matches(st, "live_box", 0x9999);  // the scenario file was edited since
    ADD_FAILURE() << "a state of an edited scenario file was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "scenario_hash");
    EXPECT_NE(std::string(e.what()).find(path + ":4:"), std::string::npos) << e.what();
  }

  LiveRun b;
  ASSERT_TRUE(b.run.advance_to(60));
  const uint64_t before = b.run.hash();
  // bytes that do not fit this simulation (a state cut short, its hash made to match)
  SavedState cut = st;
  cut.bytes.resize(cut.bytes.size() / 2);
  cut.state_hash = saved_state_hash(cut.bytes);
  try {
    b.run.runner().load_state(cut);
    ADD_FAILURE() << "a state of the wrong size was loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "bytes") << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  // bytes that do not match their hash
  SavedState damaged = st;
  damaged.bytes[damaged.bytes.size() / 3] ^= 0x40;
  try {
    b.run.runner().load_state(damaged);
    ADD_FAILURE() << "a damaged state was loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "state_hash") << e.what();
  }
  EXPECT_EQ(b.run.tick(), 60);
  EXPECT_EQ(b.run.hash(), before) << "a refused load changed the simulation";
  EXPECT_FALSE(b.run.faulted());

  // through the threaded loop: the error reaches the caller, the physics runs on untouched
  Scene sc = test::make_live_scene();
  LoopOptions o;
  o.log_timing = false;
  o.as_fast_as_possible = true;
  o.stop_at_tick = 80;
  PhysicsLoop loop(*sc.sim, o);
  loop.start();
  loop.wait_for_tick(80);
  EXPECT_THROW(loop.load_state(cut), InputError);
  loop.stop();
  EXPECT_EQ(loop.tick(), 80);
  EXPECT_FALSE(loop.faulted());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ps
