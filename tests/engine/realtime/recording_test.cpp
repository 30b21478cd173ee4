// Record and replay (engine/realtime/recording.h): a live threaded run recorded as it goes
// replays in lock-step to the same hash, bit for bit; the file round-trips every double
// exactly; malformed recordings and scripts, and recordings of another scenario or version, are
// refused with file:line.
#include "engine/realtime/recording.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/physics_loop.h"
#include "engine/util/error.h"
#include "tests/engine/realtime/live_scene.h"
#include "engine/tools/needle/needle.h"

namespace ps {
namespace {

std::string temp_dir() {
  const auto d = std::filesystem::temp_directory_path() /
                 ("ps_rec_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::create_directories(d);
  return d.string();
}

TEST(Recording, LiveThreadedRunRecordedThenReplayedGivesTheSameHash) {
  const std::string path = temp_dir() + "/live.rec";
  constexpr int64_t kTicks = 450;
  uint64_t live_hash = 0;
  Scene sc = test::make_live_scene();
  sc.content_hash = 0x1234;  // built from text: any identity, checked below
  {
    const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
    CommandPlayer p(script_commands(s, sc));
    RecordingWriter rec(path, RecordingHeader{sc.spec.name, sc.content_hash, sc.model->dt, sc.model->substeps});
    LoopOptions opt;
    opt.stop_at_tick = kTicks;
    opt.log_timing = false;
    opt.factor = 4.0;  // paced (4x real time), not lock-step
    PhysicsLoop loop(*sc.sim, opt);
    loop.add_source(&p);
    loop.applier().set_observer(&rec);
    // the UI thread also pushes commands while it runs: they are recorded at the tick applied
    loop.start();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    Command c;
    c.kind = CommandKind::NeedleRotate;
    c.tool = static_cast<int16_t>(sc.tools.index<NeedleTool>());
    c.item = 0;
    c.needle.angle = 0.25;
    c.tick = loop.next_tick();
    ASSERT_TRUE(loop.queue().push(c));
    loop.wait_for_tick(kTicks);
    loop.stop();
    live_hash = sc.sim->hash();
    rec.finish(loop.tick(), live_hash);
    EXPECT_EQ(rec.dropped(), 0);
    EXPECT_EQ(loop.applier().applied(), 11 + 1);  // the script's entries up to tick 400, and the rotate
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
  const Recording r = parse_recording_file(path);
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.end_tick, kTicks);
  EXPECT_EQ(r.end_hash, live_hash);
  EXPECT_EQ(r.commands.size(), 12u);
  check_recording_matches(r, RecordingHeader{"live_box", 0x1234, sc.model->dt, sc.model->substeps});
  // replay in lock-step, twice (any speed: no clock involved)
  for (int k = 0; k < 2; ++k) {
    Scene rs = test::make_live_scene();
    CommandPlayer p(r.commands);
    LockstepRunner run(*rs.sim);
    run.add_source(&p);
    ASSERT_TRUE(run.advance_to(r.end_tick));
    EXPECT_EQ(hex16(run.hash()), hex16(live_hash));
  }
}

TEST(Recording, CommandLinesRoundTripEveryBit) {
  // one command of each payload, with values whose text must keep every bit
  Command probe;
  probe.kind = CommandKind::ProbeMove;
  probe.tick = 123456789;
  probe.tool = 2;
  probe.probe.insertion = 0.1 + 0.2;
  probe.probe.offset[1] = -1.0 / 3.0;
  probe.probe.yaw = -0.0;
  probe.probe.duration = 1e-300;
  Command fill;
  fill.kind = CommandKind::FillTo;
  fill.tick = 123456790;
  fill.tool = 1;
  fill.fill.component = 3;
  fill.fill.value = 5e-324;  // the smallest subnormal
  fill.fill.duration = 0.7;
  Command aim;
  aim.kind = CommandKind::NeedleAim;
  aim.tick = 123456791;
  aim.item = 7;
  aim.needle.pos[2] = 3.141592653589793;
  aim.needle.dir[0] = -0.0;
  aim.needle.speed = -2.5e-3;
  Command depth;
  depth.kind = CommandKind::NeedleDepth;
  depth.tick = 123456792;
  depth.needle.depth = 0.0417;
  depth.needle.speed = 0.02;
  Command hole;
  hole.kind = CommandKind::SelectHole;
  hole.tick = 123456793;
  hole.needle.col = 4;
  hole.needle.row = 11;
  Command rotate;
  rotate.kind = CommandKind::NeedleRotate;
  rotate.tick = 123456794;
  rotate.needle.angle = 1.0 / 7.0;
  const Command in[] = {probe, fill, aim, depth, hole, rotate};
  std::string text = std::string("prostatesim-recording 1\nprogram ") + kProgramVersion +
                     "\nscenario s\nscenario_hash 0123456789abcdef\ndt 0.001\nsubsteps 2\n";
  for (const Command& c : in) text += format_command_line(c) + "\n";
  const Recording r = parse_recording_text(text, "x.rec");
  ASSERT_EQ(r.commands.size(), 6u);
  auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (size_t i = 0; i < 6; ++i) {
    const Command &c = in[i], &d = r.commands[i];
    EXPECT_EQ(d.kind, c.kind);
    EXPECT_EQ(d.tick, c.tick);
    EXPECT_EQ(d.tool, c.tool);
    EXPECT_EQ(d.item, c.item);
    EXPECT_TRUE(same(d.probe.insertion, c.probe.insertion) && same(d.probe.roll, c.probe.roll) && same(d.probe.tilt, c.probe.tilt) &&
                same(d.probe.yaw, c.probe.yaw) && same(d.probe.duration, c.probe.duration))
        << i;
    for (int k = 0; k < 3; ++k)
      EXPECT_TRUE(same(d.probe.offset[k], c.probe.offset[k]) && same(d.needle.pos[k], c.needle.pos[k]) &&
                  same(d.needle.dir[k], c.needle.dir[k]))
          << i;
    EXPECT_EQ(d.fill.component, c.fill.component);
    EXPECT_TRUE(same(d.fill.value, c.fill.value) && same(d.fill.duration, c.fill.duration)) << i;
    EXPECT_TRUE(same(d.needle.speed, c.needle.speed) && same(d.needle.angle, c.needle.angle) && same(d.needle.depth, c.needle.depth)) << i;
    EXPECT_EQ(d.needle.col, c.needle.col);
    EXPECT_EQ(d.needle.row, c.needle.row);
  }
  EXPECT_FALSE(r.complete);  // no end line: a run cut short
  EXPECT_EQ(r.header.scenario_hash, 0x0123456789abcdefull);
}

// Expects InputError whose message starts with file:line.
void expect_bad_recording(const std::string& text, int line, const std::string& words) {
  try {
    parse_recording_text(text, "bad.rec");
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("bad.rec:" + std::to_string(line) + ":", 0), 0u) << m;
    EXPECT_NE(m.find(words), std::string::npos) << m;
  }
}

TEST(Recording, MalformedRecordingsNameFileAndLine) {
  const std::string head = std::string("prostatesim-recording 1\nprogram ") + kProgramVersion +
                           "\nscenario s\nscenario_hash 0123456789abcdef\ndt 0.001\nsubsteps 1\n";
  Command c;
  c.tick = 5;
  const std::string ok = format_command_line(c);
  c.tick = 3;
  const std::string back = format_command_line(c);
  expect_bad_recording("hello\n", 1, "not a ProstateSim recording");
  expect_bad_recording("prostatesim-recording 3\n", 1, "version 3");
  expect_bad_recording("prostatesim-recording 1\nprogram 0.0\n", 2, "recorded by prostatesim 0.0");
  expect_bad_recording(head + ok + "\n" + back + "\n", 8, "ticks go backwards");
  std::string unknown = ok;
  unknown.replace(unknown.find("probe_move"), 10, "teleport_xx");
  expect_bad_recording(head + unknown + "\n", 7, "unknown command 'teleport_xx'");
  expect_bad_recording(head + "c 1 probe_move 0\n", 7, "expected 22 fields");
  std::string nan = ok;
  nan.replace(nan.rfind(' '), std::string::npos, " nan");
  expect_bad_recording(head + nan + "\n", 7, "finite number");
  expect_bad_recording(head + "end 10 xyz\n", 7, "16 hex digits");
  expect_bad_recording(head + "end 10 0123456789abcdef\n" + ok + "\n", 8, "after the 'end' line");
  expect_bad_recording("prostatesim-recording 1\n" + ok + "\n", 2, "header is complete");
  // another scenario
  const Recording r = parse_recording_text(head, "other.rec");
  try {
    check_recording_matches(r, RecordingHeader{"s", 0x1111, 0.001, 1});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("other.rec:4:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("scenario file differs"), std::string::npos) << e.what();
  }
}

void expect_bad_script(const std::string& text, int line, const std::string& words) {
  try {
    const Script s = parse_script_text(text, "bad.yaml");
    Scene sc = test::make_live_scene();
    script_commands(s, sc);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("bad.yaml:" + std::to_string(line) + ":", 0), 0u) << m;
    EXPECT_NE(m.find(words), std::string::npos) << m;
  }
}

TEST(Script, MalformedScriptsNameFileAndLine) {
  expect_bad_script("timeline: [ {t: 1, fire: gun}\n", 2, "not valid YAML");
  expect_bad_script("timeline:\n  - {t: 0.1, teleport: gun}\n", 2, "unknown action");
  expect_bad_script("timeline:\n  - {t: 0.5, fire: gun}\n  - {t: 0.2, fire: gun}\n", 3, "time goes backwards");
  expect_bad_script("timeline:\n  - {t: 0.1, fire: nobody}\n", 2, "no needle named 'nobody'");
  expect_bad_script("timeline:\n  - {t: 0.1, needle: gun}\n", 2, "depth_mm");
  expect_bad_script("timeline:\n  - {t: 0.1, needle: gun, depth_mm: x}\n", 2, "expected a number");
  expect_bad_script("timeline:\n  - {t: 0.1, fire: gun, select: gun}\n", 2, "two actions");
  expect_bad_script("scenario: brachytherapy\ntimeline:\n  - {t: 0.1, fire: gun}\n", 1, "written for scenario 'brachytherapy'");
  expect_bad_script("timeline:\n  - {t: 0.1, probe: {depth_mm: 3}}\n", 2, "unknown key");
  expect_bad_script("duration_s: 0.1\ntimeline:\n  - {t: 0.5, fire: gun}\n", 3, "after the end");
}

TEST(Script, ShippedScriptsParse) {
  for (const char* f : {"/config/scripts/biopsy.yaml", "/config/scripts/brachytherapy.yaml"}) {
    const Script s = parse_script_file(std::string(PROSTATESIM_SOURCE_DIR) + f);
    EXPECT_GT(s.entries.size(), 3u) << f;
    EXPECT_LT(s.duration, 10.0) << f;   // under 10 s of simulated time
  }
}

TEST(Script, NeedleKeysInterpolateLinearly) {
  const Script s = parse_script_text(test::live_script_yaml(), "live.yaml");
  EXPECT_DOUBLE_EQ(script_needle_depth(s, "gun", 0.05), 0.0);
  EXPECT_NEAR(script_needle_depth(s, "gun", 0.15), 0.011, 1e-12);
  EXPECT_NEAR(script_needle_depth(s, "gun", 0.45), 0.022 - 0.017 * 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(script_needle_depth(s, "gun", 9.0), 0.005);
  EXPECT_TRUE(std::isnan(script_needle_depth(s, "nobody", 0.1)));
}

}  // namespace
}  // namespace ps
