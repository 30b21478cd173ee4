// Determinism of the live path (engine/realtime/lockstep.h, tick_runner.h, script.h): the same
// script gives the same whole-simulation hash on three runs; save/restore reproduces the bits;
// the hash covers tool state; and, as Box2D does, a fixed expected hash of a short scripted run,
// so a change that alters results anywhere is seen (update kExpectedHash in the commit that
// changes results, and say so in its message).
#include "engine/realtime/lockstep.h"

#include <gtest/gtest.h>

#include <cinttypes>

#include "engine/realtime/recording.h"
#include "engine/realtime/script.h"
#include "engine/tools/needle/needle.h"
#include "tests/engine/realtime/live_scene.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/tool_kind.h"

namespace ps {
namespace {

struct ScriptRun {
  uint64_t hash = 0;
  uint64_t state_hash = 0;         // hash_state: State alone (the physics), no tool state
  int64_t applied = 0, refused = 0;
  std::vector<SnapshotEvent> events;
};

ScriptRun run_script(int64_t ticks) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  ScriptRun r;
  for (int64_t t = 0; t < ticks; t += 50) {
    EXPECT_TRUE(run.advance_to(std::min(ticks, t + 50))) << sc.sim->state().fault.describe(*sc.model);
    const Snapshot& snap = run.snapshot();
    r.events.insert(r.events.end(), snap.events.begin(), snap.events.end());
  }
  r.hash = run.hash();
  r.state_hash = hash_state(sc.sim->state());
  r.applied = run.applier().applied();
  r.refused = run.applier().refused();
  for (int i = 0; i < run.applier().refusals().size(); ++i) ADD_FAILURE() << run.applier().refusals().at(i).describe();
  return r;
}

TEST(Lockstep, SameScriptSameHashOnThreeRunsAndEveryInstrumentActs) {
  const ScriptRun a = run_script(600), b = run_script(600), c = run_script(600);
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(a.hash, c.hash);
  EXPECT_EQ(a.applied, 13);  // every script entry was taken
  EXPECT_EQ(a.refused, 0);
  // the instruments did what the script says: punctures, a core, seeds
  int punctures = 0, cores = 0, seeds = 0;
  for (const SnapshotEvent& e : a.events) {
    punctures += e.kind == static_cast<uint8_t>(NeedleEventKind::Puncture);
    cores += e.kind == static_cast<uint8_t>(NeedleEventKind::Core);
    seeds += e.kind == static_cast<uint8_t>(NeedleEventKind::Seed);
  }
  EXPECT_GE(punctures, 2);
  EXPECT_EQ(cores, 1);
  EXPECT_EQ(seeds, 2);   // one by command, one on the pull-back
  std::printf("live_box script, 600 ticks: hash %s, %d punctures, %d core, %d seeds\n", hex16(a.hash).c_str(), punctures, cores, seeds);
}

// Box2D-style: the expected hash of this run on this program. A commit that changes it changes
// simulation results somewhere (physics, tools, scene compile, command handling) and must say so.
TEST(Lockstep, FixedExpectedHashOfAShortScriptedRun) {
  constexpr uint64_t kExpectedHash = 0xcb8cf909fe67fadeull;
  // State alone (positions, velocities, every State field; no tool state): changes only when the
  // physics does, so a commit that changes kExpectedHash but not this one changed tool bookkeeping
  constexpr uint64_t kExpectedStateHash = 0x09bdb26603003026ull;
  const ScriptRun r = run_script(300);
  EXPECT_EQ(hex16(r.hash), hex16(kExpectedHash)) << "results changed: if intended, update kExpectedHash and say so in the commit";
  EXPECT_EQ(hex16(r.state_hash), hex16(kExpectedStateHash)) << "physics changed: if intended, update kExpectedStateHash and say so in the commit";
}

TEST(Lockstep, SaveRestoreReproducesTheBitsAndTheHashCoversToolState) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  ASSERT_TRUE(run.advance_to(280));  // needles inside tissue, gun about to fire
  std::vector<uint8_t> saved;
  sc.sim->save(saved);
  const uint64_t h_saved = sc.sim->hash();
  ASSERT_TRUE(run.advance_to(400));
  const uint64_t h400 = sc.sim->hash();
  // back to tick 280 and the same commands again: the same bits at 400
  sc.sim->restore(saved);
  EXPECT_EQ(sc.sim->hash(), h_saved);
  Scene sc2 = test::make_live_scene();  // a second simulation restored from the save
  sc2.sim->restore(saved);
  EXPECT_EQ(sc2.sim->hash(), h_saved);
  std::vector<Command> rest;  // the script's commands from tick 280 on
  for (const Command& c : script_commands(s, sc2))
    if (c.tick >= 280) rest.push_back(c);
  CommandPlayer p2(rest);
  CommandApplier ap2(*sc2.sim);
  for (int64_t t = 280; t < 400; ++t) {
    p2.poll(t, *sc2.sim, ap2);
    ASSERT_TRUE(sc2.sim->tick());
  }
  EXPECT_EQ(sc2.sim->hash(), h400);
  // tool state is in the hash: the same State with another needle command hashes differently
  Scene a = test::make_live_scene(), b = test::make_live_scene();
  EXPECT_EQ(a.sim->hash(), b.sim->hash());
  EXPECT_EQ(hash_state(a.sim->state()), hash_state(b.sim->state()));
  Command c;
  c.kind = CommandKind::NeedleRotate;
  c.tool = static_cast<int16_t>(b.tools.index<NeedleTool>());
  c.item = 0;
  c.needle.angle = 0.5;
  CommandApplier ap(*b.sim);
  ASSERT_TRUE(ap.apply(c, 0));
  EXPECT_EQ(hash_state(a.sim->state()), hash_state(b.sim->state()));  // the old hash does not see it
  EXPECT_NE(a.sim->hash(), b.sim->hash());
  // restoring into a simulation of another scenario is refused, not read past the end
  Scene other = build_scene(parse_scenario_text(test::read_text(std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml"),
                                                "probe_pelvis_box.yaml"));
  EXPECT_THROW(other.sim->restore(saved), std::runtime_error);
}

TEST(Lockstep, ResetGoesBackToTheFirstTickBitForBit) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  const uint64_t h0 = run.hash();
  ASSERT_TRUE(run.advance_to(150));
  const uint64_t h150 = run.hash();
  run.reset();
  EXPECT_EQ(run.tick(), 0);
  EXPECT_EQ(run.hash(), h0);
  ASSERT_TRUE(run.advance_to(150));
  EXPECT_EQ(run.hash(), h150);
}

TEST(Lockstep, SnapshotCarriesPositionsReadoutsAndRefusals) {
  Scene sc = test::make_live_scene();
  LockstepRunner run(*sc.sim);
  Command bad;
  bad.kind = CommandKind::FireGun;
  bad.tool = static_cast<int16_t>(sc.tools.index<NeedleTool>());
  bad.item = 1;  // the seeder has no gun
  ASSERT_TRUE(run.queue().push(bad));
  ASSERT_TRUE(run.advance_to(2));
  const Snapshot& s = run.snapshot(true);
  EXPECT_EQ(s.tick, 2);
  EXPECT_DOUBLE_EQ(s.time, sc.sim->state().time);
  ASSERT_EQ(s.x.size(), 3 * sc.sim->state().x.size());
  EXPECT_EQ(s.x[0], static_cast<float>(sc.sim->state().x[0].x()));
  ASSERT_EQ(s.tools.size(), sc.sim->tools().size());
  const ToolReadout& needle = s.tools[sc.tools.index<NeedleTool>()];
  EXPECT_EQ(readout_kind(needle), &NeedleTool::kind());
  EXPECT_EQ(needle.carries, kCarriesInsertion);
  EXPECT_STREQ(s.tools[sc.tools.index<NeedleTool>()].name.data(), "gun");
  EXPECT_EQ(readout_kind(s.tools[sc.tools.index<ProbeTool>()]), &ProbeTool::kind());
  EXPECT_EQ(s.tools[sc.tools.index<ProbeTool>()].carries, kCarriesImaging);
  EXPECT_EQ(readout_kind(s.tools[sc.tools.index<FillingTool>()]), &FillingTool::kind());
  EXPECT_EQ(s.tools[sc.tools.index<FillingTool>()].carries, kCarriesVolume);
  EXPECT_EQ(s.state_hash, sc.sim->hash());
  ASSERT_EQ(s.events.size(), 1u);
  EXPECT_EQ(s.events[0].kind, kSnapshotEventRefused);
  EXPECT_NE(std::string(s.events[0].text.data()).find("no biopsy gun"), std::string::npos) << s.events[0].text.data();
  EXPECT_TRUE(run.snapshot().events.empty());  // events are since the previous snapshot
}

}  // namespace
}  // namespace ps
