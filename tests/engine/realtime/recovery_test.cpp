// Recovery from a simulation fault (issue 14 item 2; engine/realtime/tick_runner.h,
// physics_loop.h, state_file.h): a NaN injected by the loop before a tick (never inside the step)
// is caught by the step's own check; the runner stops with the tick, time and particle; the last
// good state is the state before that tick, bit for bit (restored and run on, it gives the clean
// run's hash), survives a round trip through a state file, and reset() goes back to the start.
// The threaded loop does the same without the program stopping, and an exception on the physics
// thread is caught there as an internal error. A watchdog finding (energy growth) is a fault too.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/physics_loop.h"
#include "engine/realtime/state_file.h"
#include "engine/util/error.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

uint64_t clean_hash(int64_t ticks) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  EXPECT_TRUE(run.advance_to(ticks));
  return run.hash();
}

TEST(Recovery, InjectedNaNStopsTheRunnerAndTheLastGoodStateIsTheTickBefore) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  run.runner().keep_last_good(true);
  const uint64_t initial = run.hash();
  run.runner().inject_fault(120, 7);
  EXPECT_FALSE(run.advance_to(200));
  EXPECT_TRUE(run.faulted());
  EXPECT_EQ(run.tick(), 120);
  const std::string& why = run.runner().fault_text();
  EXPECT_NE(why.find("tick 120:"), std::string::npos) << why;
  EXPECT_NE(why.find("particle"), std::string::npos) << why;
  EXPECT_NE(why.find("t=0.12"), std::string::npos) << why;
  EXPECT_FALSE(run.step());  // stays stopped
  const Snapshot& snap = run.snapshot();
  EXPECT_TRUE(snap.faulted);
  EXPECT_NE(std::string(snap.fault.data()).find("tick 120"), std::string::npos) << snap.fault.data();

  SavedState good;
  ASSERT_TRUE(run.runner().last_good(good));
  EXPECT_EQ(good.tick, 120);
  EXPECT_NEAR(good.time, 0.12, 1e-12);
  EXPECT_EQ(good.fault, why);
  // the last good state, through a file, restored into a fresh scene and run on clean: the very
  // bits of a run that never faulted
  good.scenario = sc.spec.name;
  const std::string path = (std::filesystem::temp_directory_path() / "prostatesim_recovery_test.state").string();
  write_state_file(path, good);
  const SavedState back = read_state_file(path);
  EXPECT_EQ(back.bytes, good.bytes);
  EXPECT_EQ(back.tick, 120);
  EXPECT_EQ(back.scenario, "live_box");
  Scene fresh = test::make_live_scene();
  fresh.sim->restore(back.bytes);
  EXPECT_EQ(fresh.sim->hash(), back.state_hash);
  EXPECT_EQ(back.state_hash, clean_hash(120));
  // a damaged state file is bad input naming file:line
  std::string text = test::read_text(path);
  text[text.size() - 3] ^= 0x5a;
  std::ofstream(path, std::ios::binary) << text;
  try {
    read_state_file(path);
    ADD_FAILURE() << "a damaged state file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":7:"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);

  // reset: back to the start, and the run goes on clean (the injection fires once)
  run.reset();
  EXPECT_FALSE(run.faulted());
  EXPECT_EQ(run.hash(), initial);
  EXPECT_TRUE(run.runner().fault_text().empty());
  EXPECT_TRUE(run.advance_to(200));
  EXPECT_EQ(run.hash(), clean_hash(200));
}

// A source that applies `per_tick` bladder filling commands before every tick up to `until`:
// more commands between two checkpoints than the runner's log holds (TickRunner::kLogCapacity),
// so the runner takes checkpoints early.
class FloodSource final : public CommandSource {
 public:
  FloodSource(int component, int per_tick, int64_t until) : component_(component), per_tick_(per_tick), until_(until) {}
  void poll(int64_t tick, const Simulation&, CommandApplier& apply) override {
    if (tick >= until_) return;
    for (int i = 0; i < per_tick_; ++i) {
      Command c;
      c.kind = CommandKind::FillRate;
      c.fill.component = component_;
      c.fill.value = (50.0 + (tick + i) % 7) * 1e-6;  // [m^3/s]; the last one of a tick holds
      apply.apply(c, tick);
    }
  }

 private:
  int component_, per_tick_;
  int64_t until_;
};

// The last good state is not saved before every tick: the runner keeps a checkpoint every
// kCheckpointTicks ticks and the commands applied since, and rebuilds it on a fault. Faults just
// before, at and after a checkpoint, after the script's commands, with a log that overflowed
// (early checkpoints), and an exception thrown mid-tick: each time the rebuilt state is the
// clean run's state at that tick, bit for bit, and the faulted state is left as it was.
TEST(Recovery, TheLastGoodStateIsRebuiltFromACheckpointBitForBit) {
  const Script script = parse_script_text(test::live_script_yaml(), "live.yaml");
  auto bladder = [](const Scene& sc) { return sc.model->find_component("bladder"); };
  struct Case {
    int64_t tick;
    bool internal;
  };
  for (const Case c : {Case{1, false}, Case{99, false}, Case{100, false}, Case{101, false}, Case{130, true}, Case{262, false}}) {
    // the clean run, no recovery kept
    Scene ref = test::make_live_scene();
    ASSERT_GE(bladder(ref), 0);
    CommandPlayer ref_player(script_commands(script, ref));
    FloodSource ref_flood(bladder(ref), 60, 150);
    LockstepRunner clean(*ref.sim);
    clean.add_source(&ref_player);
    clean.add_source(&ref_flood);
    ASSERT_TRUE(clean.advance_to(c.tick));
    const uint64_t want = clean.hash();

    Scene sc = test::make_live_scene();
    CommandPlayer player(script_commands(script, sc));
    FloodSource flood(bladder(sc), 60, 150);
    LockstepRunner run(*sc.sim);
    run.add_source(&player);
    run.add_source(&flood);
    run.runner().keep_last_good(true);
    run.runner().inject_fault(c.tick, 5, c.internal);
    bool threw = false;
    try {
      EXPECT_FALSE(run.advance_to(c.tick + 50)) << "tick " << c.tick;
    } catch (const std::logic_error&) {
      threw = true;
    }
    EXPECT_EQ(threw, c.internal) << "tick " << c.tick;
    EXPECT_EQ(run.tick(), c.tick);
    std::vector<uint8_t> faulted;
    sc.sim->save(faulted);
    SavedState good;
    ASSERT_TRUE(run.runner().last_good(good));
    EXPECT_EQ(good.tick, c.tick);
    EXPECT_NEAR(good.time, c.tick * sc.model->dt, 1e-12);
    EXPECT_EQ(good.state_hash, want) << "fault at tick " << c.tick;
    std::vector<uint8_t> after;
    sc.sim->save(after);
    EXPECT_TRUE(after == faulted) << "the faulted state changed, tick " << c.tick;
  }
}

TEST(Recovery, ThreadedLoopStopsShowsTheFaultSavesAndResets) {
  Scene sc = test::make_live_scene();
  LoopOptions o;
  o.as_fast_as_possible = true;
  o.log_timing = false;
  o.stop_at_tick = 150;
  PhysicsLoop loop(*sc.sim, o);
  loop.keep_last_good(true);
  loop.inject_fault(40, 3);
  loop.start();
  loop.wait_for_tick(150);
  EXPECT_TRUE(loop.faulted());
  EXPECT_FALSE(loop.internal_error());
  EXPECT_EQ(loop.tick(), 40);
  EXPECT_NE(loop.fault_text().find("tick 40:"), std::string::npos) << loop.fault_text();
  SavedState st;
  ASSERT_TRUE(loop.last_good_state(st));
  EXPECT_EQ(st.tick, 40);
  // the reader sees the fault in the snapshot
  for (int i = 0; i < 200 && !loop.snapshot().faulted; ++i) {
    loop.update_snapshot();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_TRUE(loop.snapshot().faulted);
  EXPECT_NE(std::string(loop.snapshot().fault.data()).find("tick 40"), std::string::npos);
  // reset from the UI thread: the physics runs again, to the stop tick
  loop.reset();
  loop.resume();
  for (int i = 0; i < 20000 && (loop.faulted() || loop.tick() < 150); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_FALSE(loop.faulted());
  EXPECT_EQ(loop.tick(), 150);
  EXPECT_FALSE(loop.last_good_state(st));  // cleared by the reset
  loop.stop();
}

TEST(Recovery, AnExceptionOnThePhysicsThreadIsCaughtAsAnInternalError) {
  Scene sc = test::make_live_scene();
  LoopOptions o;
  o.as_fast_as_possible = true;
  o.log_timing = false;
  PhysicsLoop loop(*sc.sim, o);
  loop.keep_last_good(true);
  loop.inject_fault(25, 0, /*internal=*/true);
  loop.start();
  loop.wait_for_tick(100);
  loop.stop();  // joins: the thread ended without terminating the program
  EXPECT_TRUE(loop.faulted());
  EXPECT_TRUE(loop.internal_error());
  EXPECT_NE(loop.fault_text().find("internal error on the physics thread at tick 25"), std::string::npos) << loop.fault_text();
  SavedState st;
  EXPECT_TRUE(loop.last_good_state(st));
  EXPECT_EQ(st.tick, 25);
}

TEST(Recovery, AWatchdogFindingIsAFaultWithItsParticle) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  WatchLimits lim;
  lim.max_speed = 1e-4;  // the probe pushes tissue faster than 0.1 mm/s within the first ticks
  const Watchdog dog(*sc.model, lim);
  run.runner().set_watchdog(&dog);
  EXPECT_FALSE(run.advance_to(300));
  const std::string& why = run.runner().fault_text();
  EXPECT_NE(why.find("watchdog: energy growth"), std::string::npos) << why;
  EXPECT_NE(why.find("particle"), std::string::npos) << why;
  // with the default limits the same script runs clean
  Scene sc2 = test::make_live_scene();
  CommandPlayer player2(script_commands(s, sc2));
  LockstepRunner run2(*sc2.sim);
  run2.add_source(&player2);
  const Watchdog dog2(*sc2.model);
  run2.runner().set_watchdog(&dog2);
  EXPECT_TRUE(run2.advance_to(600)) << run2.runner().fault_text();
}

}  // namespace
}  // namespace ps
