// Command application and ticks do not allocate (engine/realtime/command_apply.h, tick_runner.h;
// issue 10 "no allocation on the physics thread"): every command kind of the live_box script and
// of the UI queue, including the commands a tool adjusts to its limits (a fill rate above the
// limit, a fill target outside 0.1x..10x the rest volume, a fill target or a probe move faster
// than the limits: each leaves a record in the tool's fixed report ring, tools/tool_reports.h)
// and the commands the tools refuse (a tilt beyond 45 degrees, an organ that is not filled, a
// non-finite target, a gun on a needle without one, a NaN aim), applied through CommandApplier and counted with the engine tests'
// replacement operator new (tests/engine/counting_allocator.h):
//  - on a first (cold) run of a fresh scene, applying each command allocates nothing, and neither
//    does any whole tick (commands, step, last-good save, watchdog, periodic hashes) after the
//    first one;
//  - once warm, a whole tick with those hooks and a published snapshot allocates nothing.
// The reports are then read and formatted on the reader's side, where allocating is allowed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "engine/realtime/lockstep.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/probe/probe.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/realtime/live_scene.h"
#include "engine/tools/needle/needle.h"

namespace ps {
namespace {

// Wraps a source and counts the allocations made while it applies its commands.
class CountingSource final : public CommandSource {
 public:
  explicit CountingSource(CommandSource& inner) : inner_(inner) {}
  void poll(int64_t tick, const Simulation& sim, CommandApplier& apply) override {
    const int64_t applied = apply.applied() + apply.refused();
    const long before = test::allocation_count();
    inner_.poll(tick, sim, apply);
    const long n = test::allocation_count() - before;
    allocations += n;
    if (n > 0 && apply.applied() + apply.refused() > applied) per_tick[tick] = n;
  }
  void rewind() override { inner_.rewind(); }
  long allocations = 0;
  std::map<int64_t, long> per_tick;

 private:
  CommandSource& inner_;
};

class NullHashes final : public HashObserver {
 public:
  void state_hash(int64_t, uint64_t h) override { last = h; }
  uint64_t last = 0;
};

double bladder_rest(const Scene& sc) {
  const int b = sc.model->find_component("bladder");
  for (const auto& surf : sc.model->surfaces)
    if (surf.volume_constrained && surf.component == b) return surf.rest_volume;
  return 0.0;
}

Command fill(int64_t tick, CommandKind kind, int component, double value, double duration = 0.0) {
  Command c;
  c.tick = tick;
  c.kind = kind;
  c.fill.component = component;
  c.fill.value = value;
  c.fill.duration = duration;
  return c;
}

// Commands the tools take but adjust, and commands they refuse, on top of the live_box script
// (which itself has a live fill_rate that the 0.1x..10x volume range stops: a report).
struct Extra {
  std::vector<Command> cmds;
  int adjusted_commands = 0, refused = 0;
};
Extra extra_commands(const Scene& sc) {
  const int bladder = sc.model->find_component("bladder"), prostate = sc.model->find_component("prostate");
  const double rest = bladder_rest(sc);
  Extra e;
  // 5000 ml/s against the scene's 1000 ml/s limit: clamped (and stopped by the volume range)
  e.cmds.push_back(fill(60, CommandKind::FillRate, bladder, 5e-3));
  e.cmds.push_back(fill(62, CommandKind::FillRate, bladder, 0.0));  // held after 2 ms
  // 20x the rest volume: clamped to 10x, and lengthened to the rate limit; superseded a tick later
  e.cmds.push_back(fill(130, CommandKind::FillTo, bladder, 20.0 * rest, 1e-3));
  e.cmds.push_back(fill(131, CommandKind::FillTo, bladder, 1.2 * rest, 0.2));
  e.adjusted_commands += 2;
  // a probe move of 4 mm in 1 ms (200 mm/s limit): lengthened
  Command pm;
  pm.tick = 150;
  pm.kind = CommandKind::ProbeMove;
  pm.probe.insertion = 0.056;
  pm.probe.tilt = 2.0 * 3.141592653589793 / 180.0;
  pm.probe.duration = 1e-3;
  e.cmds.push_back(pm);
  e.adjusted_commands += 1;
  // refused: a tilt of 60 degrees, the prostate (not filled), a NaN target, a negative duration
  Command tilt = pm;
  tilt.tick = 160;
  tilt.probe.tilt = 60.0 * 3.141592653589793 / 180.0;
  e.cmds.push_back(tilt);
  e.cmds.push_back(fill(170, CommandKind::FillRate, prostate, 1e-6));
  e.cmds.push_back(fill(171, CommandKind::FillTo, bladder, std::nan(""), 0.1));
  e.cmds.push_back(fill(172, CommandKind::FillTo, bladder, rest, -1.0));
  // the needles' refusals: the seeder has no gun; an aim with a NaN tip
  Command gun;
  gun.tick = 173;
  gun.kind = CommandKind::FireGun;
  gun.tool = static_cast<int16_t>(sc.tools.index<NeedleTool>());
  gun.item = 1;
  e.cmds.push_back(gun);
  Command aim = gun;
  aim.tick = 174;
  aim.kind = CommandKind::NeedleAim;
  aim.item = 0;
  aim.needle.pos[0] = std::nan("");
  e.cmds.push_back(aim);
  e.refused = 6;
  return e;
}

// The queue's command kinds the script does not use: probe pose, fill to, needle release, advance.
Command queue_command(const Scene& sc, int64_t t) {
  Command c;
  c.tick = t;
  if (t == 100) {
    c = fill(t, CommandKind::FillTo, sc.model->find_component("bladder"), 1.5 * bladder_rest(sc), 0.2);  // within limits
  } else if (t == 450) {
    c.kind = CommandKind::ProbeMove;
    c.probe.insertion = 0.051;
    c.probe.duration = 0.05;
  } else if (t == 500) {
    c.kind = CommandKind::NeedleRelease;
    c.tool = static_cast<int16_t>(sc.tools.index<NeedleTool>());
    c.item = 0;
  } else {
    c.kind = CommandKind::NeedleAdvance;
    c.tool = static_cast<int16_t>(sc.tools.index<NeedleTool>());
    c.item = 1;
    c.needle.speed = -0.01;
  }
  return c;
}

const FillingTool& filling_of(const Scene& sc) { return *sc.tools.as<FillingTool>(); }
const ProbeTool& probe_of(const Scene& sc) {
  for (const auto& t : sc.sim->tools())
    if (const auto* p = dynamic_cast<const ProbeTool*>(t.get())) return *p;
  throw std::logic_error("no probe");
}

TEST(CommandApplyAlloc, CommandsAppliedAdjustedOrRefusedAllocateNothingOnAColdScene) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  const Extra extra = extra_commands(sc);
  CommandPlayer adjusted(extra.cmds);
  CountingSource counted(player), counted_extra(adjusted);
  LockstepRunner run(*sc.sim);
  run.add_source(&counted);
  run.add_source(&counted_extra);
  // the hooks `run` and the app turn on: last good state, watchdog, a hash every 10 ticks
  const Watchdog dog(*sc.model);
  NullHashes hashes;
  run.runner().set_watchdog(&dog);
  run.runner().keep_last_good(true);
  run.runner().set_hash_observer(&hashes, 10);
  const int64_t script_ticks = static_cast<int64_t>(player.commands().size());
  long queue_allocations = 0;
  std::map<int64_t, long> tick_allocations;
  for (int64_t t = 0; t < 600; ++t) {
    if (t == 100 || t == 450 || t == 500 || t == 520) {
      const Command c = queue_command(sc, t);
      ASSERT_TRUE(run.queue().push(c));
      const long before = test::allocation_count();
      run.applier().apply_due(run.queue(), t);
      const long n = test::allocation_count() - before;
      if (n > 0) ADD_FAILURE() << n << " allocations applying a " << command_kind_name(c.kind) << " from the queue at tick " << t;
      queue_allocations += n;
    }
    const long before = test::allocation_count();
    ASSERT_TRUE(run.step()) << run.runner().fault_text();
    const long n = test::allocation_count() - before;
    if (n > 0 && t > 0) tick_allocations[t] = n;  // tick 0 may size what the step uses lazily
  }
  EXPECT_EQ(run.applier().refused(), extra.refused);
  EXPECT_EQ(run.applier().applied(), script_ticks + 4 + static_cast<int64_t>(extra.cmds.size()) - extra.refused);
  for (const auto& [tick, n] : counted.per_tick) ADD_FAILURE() << n << " allocations applying the script's commands of tick " << tick;
  for (const auto& [tick, n] : counted_extra.per_tick) ADD_FAILURE() << n << " allocations applying the adjusted/refused commands of tick " << tick;
  for (const auto& [tick, n] : tick_allocations) ADD_FAILURE() << n << " allocations in the whole tick " << tick;
  EXPECT_EQ(counted.allocations + counted_extra.allocations + queue_allocations, 0);

  // --- reader side: the records say what was asked and what was used, and read as before ---
  const FillingTool& f = filling_of(sc);
  const double rest = bladder_rest(sc);
  bool rate_clamped = false, target_clamped = false, lengthened = false, stopped = false;
  for (int i = 0; i < f.report_ring().size(); ++i) {
    const ToolReport& r = f.report_ring().at(i);
    if (!r.live) continue;
    if (r.code == ToolReportCode::FillRateClamped) {
      rate_clamped = true;
      EXPECT_DOUBLE_EQ(r.a, 5e-3);           // asked [m^3/s]
      EXPECT_DOUBLE_EQ(r.b, f.max_rate());   // the limit
      EXPECT_DOUBLE_EQ(r.c, f.max_rate());   // used
      EXPECT_NEAR(r.time, 0.060, 1e-9);
    }
    if (r.code == ToolReportCode::FillTargetClamped) {
      target_clamped = true;
      EXPECT_DOUBLE_EQ(r.a, 20.0 * rest);
      EXPECT_NEAR(r.b, 10.0 * rest, 1e-12 * rest);
    }
    if (r.code == ToolReportCode::FillLengthened && std::abs(r.a - 10.0 * rest) < 1e-12 * rest) {
      lengthened = true;
      EXPECT_DOUBLE_EQ(r.b, 1e-3);
      EXPECT_GT(r.c, 1e-3);
    }
    stopped |= r.code == ToolReportCode::FillStops;
  }
  EXPECT_TRUE(rate_clamped);
  EXPECT_TRUE(target_clamped);
  EXPECT_TRUE(lengthened);
  EXPECT_TRUE(stopped);  // the script's 100 ml/s (open-ended) stops at the volume range
  const std::vector<std::string> text = f.reports();
  const auto has = [&](const std::vector<std::string>& lines, const std::string& what) {
    return std::any_of(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(has(text, "t=0.06 s: live filling command (bladder): fill rate 5000 ml/s exceeds the limit 1000 ml/s; clamped to 1000 ml/s"))
      << testing::PrintToString(text);
  EXPECT_TRUE(has(text, "clamped to")) << testing::PrintToString(text);
  EXPECT_TRUE(has(text, "to stay within 0.1x..10x the rest volume")) << testing::PrintToString(text);
  const ProbeTool& p = probe_of(sc);
  ASSERT_EQ(p.report_ring().size(), 1);
  const ToolReport& pr = p.report_ring().at(0);
  EXPECT_EQ(pr.code, ToolReportCode::ProbeMoveLengthened);
  EXPECT_DOUBLE_EQ(pr.a, 1e-3);
  EXPECT_GT(pr.b, 1e-3);
  EXPECT_DOUBLE_EQ(pr.c, 0.2);  // the scene's 200 mm/s
  ASSERT_EQ(p.reports().size(), 1u);
  EXPECT_NE(p.reports()[0].find("t=0.15 s: probe command lengthened from 0.001 s to "), std::string::npos) << p.reports()[0];
  EXPECT_NE(p.reports()[0].find("to respect the speed limits (200 mm/s, 180 deg/s)"), std::string::npos) << p.reports()[0];
  // the refusals name the reason (a fixed ring in the applier, formatted here)
  std::vector<std::string> refusals;
  for (int i = 0; i < run.applier().refusals().size(); ++i) refusals.push_back(run.applier().refusals().at(i).describe());
  EXPECT_TRUE(has(refusals, "tick 160: probe_move refused: tilt and yaw must be within +-45 degrees")) << testing::PrintToString(refusals);
  EXPECT_TRUE(has(refusals, "'prostate' is not a filled organ")) << testing::PrintToString(refusals);
  EXPECT_TRUE(has(refusals, "a target volume must be > 0")) << testing::PrintToString(refusals);
  EXPECT_TRUE(has(refusals, "duration: must be >= 0")) << testing::PrintToString(refusals);
  EXPECT_TRUE(has(refusals, "fire_gun refused: needle 'seeder' has no biopsy gun")) << testing::PrintToString(refusals);
  EXPECT_TRUE(has(refusals, "needle aim needs a finite tip")) << testing::PrintToString(refusals);
}

// The adjusted commands reach the snapshot as events, formatted on publishing into the event's
// fixed text (SnapshotEvent::text), with the kind kSnapshotEventAdjusted.
TEST(CommandApplyAlloc, AdjustedCommandsArePublishedAsSnapshotEvents) {
  Scene sc = test::make_live_scene();
  CommandPlayer adjusted(extra_commands(sc).cmds);
  LockstepRunner run(*sc.sim);
  run.add_source(&adjusted);
  ASSERT_TRUE(run.advance_to(200));
  std::vector<std::string> adjusted_text;
  for (const SnapshotEvent& e : run.snapshot().events)
    if (e.kind == kSnapshotEventAdjusted) adjusted_text.emplace_back(e.text.data());
  const auto has = [&](const std::string& what) {
    return std::any_of(adjusted_text.begin(), adjusted_text.end(), [&](const std::string& l) { return l.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(has("bladder: fill rate 5000 ml/s exceeds the limit 1000 ml/s; clamped to 1000 ml/s")) << testing::PrintToString(adjusted_text);
  EXPECT_TRUE(has("probe command lengthened from 0.001 s to ")) << testing::PrintToString(adjusted_text);
  EXPECT_TRUE(has("(limits 200 mm/s, 180 deg/s)")) << testing::PrintToString(adjusted_text);
  // not published twice
  ASSERT_TRUE(run.advance_to(210));
  for (const SnapshotEvent& e : run.snapshot().events) EXPECT_NE(e.kind, kSnapshotEventAdjusted) << e.text.data();
}

TEST(CommandApplyAlloc, AWarmTickWithRecoveryHashHooksAndSnapshotsAllocatesNothing) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  CommandPlayer player(script_commands(s, sc));
  CommandPlayer adjusted(extra_commands(sc).cmds);
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  run.add_source(&adjusted);
  const Watchdog dog(*sc.model);
  NullHashes hashes;
  run.runner().set_watchdog(&dog);
  run.runner().keep_last_good(true);
  run.runner().set_hash_observer(&hashes, 10);
  for (int64_t t = 0; t < 600; ++t) {  // warm: every buffer at its size, the snapshot's too
    ASSERT_TRUE(run.step()) << run.runner().fault_text();
    run.snapshot();
  }
  run.reset();
  long worst = 0;
  int64_t worst_tick = -1;
  for (int64_t t = 0; t < 600; ++t) {
    const long before = test::allocation_count();
    ASSERT_TRUE(run.step()) << run.runner().fault_text();
    run.snapshot();
    const long n = test::allocation_count() - before;
    if (n > worst) {
      worst = n;
      worst_tick = t;
    }
  }
  EXPECT_EQ(worst, 0) << "tick " << worst_tick;
  EXPECT_NE(hashes.last, 0u);
  EXPECT_GE(filling_of(sc).report_ring().size(), 4);
}

}  // namespace
}  // namespace ps
