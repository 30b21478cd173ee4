// Recovery and exit codes of `prostatesim run` / `replay` (app/cmd_run.cpp, app/cmd_replay.cpp,
// app/main.cpp): a simulation fault injected by the loop (hidden --inject-fault nan@TICK) stops
// the physics, not the program: the fault is printed with tick, time and particle, the recording
// is still finished, the last good state is written with --save-on-fault, exit 3; replaying the
// recording faults at the same tick with the same last good state. An exception on the physics
// thread (throw@TICK) is an internal error: exit 4 with a message asking for a report, the
// recording kept. A tampered recording is caught by its periodic hashes: exit 3 naming file:line
// and tick.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "tests/app/run_cli.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

std::string state_hash_of(const std::string& state_file) {
  const std::string t = test::read_text(std::filesystem::path(state_file));
  std::smatch m;
  return std::regex_search(t, m, std::regex("\nstate_hash ([0-9a-f]{16})\n")) ? m[1].str() : "";
}

TEST(RunRecovery, AFaultStopsThePhysicsPrintsItSavesTheLastGoodStateAndExits3) {
  const auto dir = test::cli_temp_dir("run_recovery");
  const std::string scene = test::write_live_scene(dir.string());
  const std::string script = (dir / "live.yaml").string();
  std::ofstream(script) << test::live_script_yaml();
  const std::string rec = (dir / "live.rec").string(), good = (dir / "good.state").string();
  const auto r = test::run_cli("run " + scene + " --script " + script + " --headless --duration 0.3 --unpaced --record " + rec +
                               " --inject-fault nan@150 --save-on-fault " + good);
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("simulation fault, the physics stopped at tick 150:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("particle 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("t=0.15"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("last good state (tick 150"), std::string::npos) << r.out;
  ASSERT_TRUE(std::filesystem::exists(good));
  ASSERT_TRUE(std::filesystem::exists(rec)) << "the session's recording was not finished";
  EXPECT_FALSE(std::filesystem::exists(rec + ".part"));
  const std::string live_good = state_hash_of(good);
  EXPECT_EQ(live_good.size(), 16u);
  // the replay meets the same fault at the same tick, with the same last good state
  const std::string good2 = (dir / "good2.state").string();
  const auto p = test::run_cli("replay " + scene + " --recording " + rec + " --inject-fault nan@150 --save-on-fault " + good2);
  EXPECT_EQ(p.code, 3) << p.out;
  EXPECT_NE(p.out.find("the replay stopped at tick 150:"), std::string::npos) << p.out;
  EXPECT_NE(p.out.find("the live run faulted at the same tick"), std::string::npos) << p.out;
  EXPECT_EQ(state_hash_of(good2), live_good);
  // the recording says where the live run faulted: a replay that does not fault there diverged
  EXPECT_NE(test::read_text(std::filesystem::path(rec)).find("\nfault 150\n"), std::string::npos);
  const auto nf = test::run_cli("replay " + scene + " --recording " + rec);
  EXPECT_EQ(nf.code, 3) << nf.out;
  EXPECT_NE(nf.out.find("the live run faulted at tick 150, the replay ran it without a fault"), std::string::npos) << nf.out;
  // without the injection the replay of the first 150 ticks ends in that very state
  const auto h = test::run_cli("replay " + scene + " --script " + script + " --duration 0.15 --hash");
  ASSERT_EQ(h.code, 0) << h.out;
  EXPECT_NE(h.out.find(live_good), std::string::npos) << h.out << " vs " << live_good;
  // a bad injection spec is bad input
  EXPECT_EQ(test::run_cli("run " + scene + " --headless --duration 0.01 --inject-fault nan").code, 2);
}

TEST(RunRecovery, AnInternalErrorOnThePhysicsThreadExits4AskingForAReport) {
  const auto dir = test::cli_temp_dir("run_internal");
  const std::string scene = test::write_live_scene(dir.string());
  const std::string rec = (dir / "i.rec").string();
  const auto r = test::run_cli("run " + scene + " --headless --duration 0.1 --unpaced --record " + rec + " --inject-fault throw@20");
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_NE(r.out.find("internal error"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("at tick 20"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Please report it"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("version: prostatesim"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(rec)) << "the recording is kept";
  // the same in the lock-step replay (the exception reaches main)
  const auto p = test::run_cli("replay " + scene + " --recording " + rec + " --inject-fault throw@10");
  EXPECT_EQ(p.code, 4) << p.out;
  EXPECT_NE(p.out.find("internal error"), std::string::npos) << p.out;
}

TEST(RunRecovery, ATamperedRecordingIsCaughtByItsHashesWithFileLineAndTick) {
  const auto dir = test::cli_temp_dir("run_tamper");
  const std::string scene = test::write_live_scene(dir.string());
  const std::string script = (dir / "live.yaml").string();
  std::ofstream(script) << test::live_script_yaml();
  const std::string rec = (dir / "t.rec").string();
  ASSERT_EQ(test::run_cli("run " + scene + " --script " + script + " --headless --duration 0.4 --unpaced --record " + rec).code, 0);
  const auto ok = test::run_cli("replay " + scene + " --recording " + rec);
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_NE(ok.out.find("4 recorded state hashes checked: all equal"), std::string::npos) << ok.out;
  // change the needle aim of tick 250 (its direction's z)
  std::string text = test::read_text(std::filesystem::path(rec));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex("\nc 250 needle_aim [^\n]*"))) << text;
  std::string line = m.str();
  line = line.substr(0, line.rfind(' ')) + " 0.001";
  const std::string bad = (dir / "tampered.rec").string();
  std::ofstream(bad) << text.substr(0, m.position()) + line + text.substr(m.position() + m.length());
  const auto r = test::run_cli("replay " + scene + " --recording " + bad);
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("replay diverged: " + bad + ":[0-9]+: tick 300:"))) << r.out;
}

}  // namespace
}  // namespace ps
