// `prostatesim run` and `prostatesim replay` (app/cmd_run.cpp, app/cmd_replay.cpp): a headless
// scripted run recorded as it goes replays to the same 16-hex-digit hash, paced or not; a
// recording of another scenario, a malformed recording or script exits 2 naming file:line.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "tests/app/run_cli.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

std::string last_line(const std::string& s) {
  std::string t = s;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const auto p = t.rfind('\n');
  return p == std::string::npos ? t : t.substr(p + 1);
}

TEST(RunReplay, HeadlessRecordedRunReplaysToTheSameHash) {
  const auto dir = test::cli_temp_dir("run_replay");
  const std::string scene = test::write_live_scene(dir.string());
  const std::string script = (dir / "live.yaml").string();
  std::ofstream(script) << test::live_script_yaml();
  const std::string rec = (dir / "live.rec").string();
  // paced at 5x real time (the threaded loop), 0.3 s simulated
  const auto run = test::run_cli("run " + scene + " --script " + script + " --headless --duration 0.3 --factor 5 --record " + rec);
  ASSERT_EQ(run.code, 0) << run.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(run.out, m, std::regex("state hash ([0-9a-f]{16})"))) << run.out;
  const std::string live = m[1];
  EXPECT_NE(run.out.find("300 ticks"), std::string::npos) << run.out;
  const auto rep = test::run_cli("replay " + scene + " --recording " + rec + " --hash");
  ASSERT_EQ(rep.code, 0) << rep.out;
  EXPECT_EQ(last_line(rep.out), live) << rep.out;
  // the script replayed directly (lock-step) and an unpaced run give the same bits too
  const auto scripted = test::run_cli("replay " + scene + " --script " + script + " --duration 0.3 --hash");
  EXPECT_EQ(last_line(scripted.out), live) << scripted.out;
  const auto unpaced = test::run_cli("run " + scene + " --script " + script + " --headless --duration 0.3 --unpaced --hash");
  EXPECT_EQ(last_line(unpaced.out), live) << unpaced.out;
}

TEST(RunReplay, BadRecordingsAndScriptsExit2WithFileAndLine) {
  const auto dir = test::cli_temp_dir("run_replay_bad");
  const std::string scene = test::write_live_scene(dir.string());
  const std::string script = (dir / "live.yaml").string();
  std::ofstream(script) << test::live_script_yaml();
  const std::string rec = (dir / "live.rec").string();
  ASSERT_EQ(test::run_cli("run " + scene + " --script " + script + " --headless --duration 0.05 --unpaced --record " + rec).code, 0);
  // the same recording against a changed scenario file
  const std::string other = (dir / "other.yaml").string();
  std::ofstream(other) << test::live_scene_yaml() << "# changed\n";
  auto r = test::run_cli("replay " + other + " --recording " + rec + " --hash");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(rec + ":4:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("scenario file differs"), std::string::npos) << r.out;
  // a malformed recording
  const std::string bad = (dir / "bad.rec").string();
  std::ofstream(bad) << "prostatesim-recording 1\nprogram 0.1\nscenario live_box\nscenario_hash 0000000000000000\ndt 0.001\nsubsteps 1\nc 5 warp\n";
  r = test::run_cli("replay " + scene + " --recording " + bad);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(bad + ":7:"), std::string::npos) << r.out;
  // a script with time going backwards
  const std::string bs = (dir / "bad.yaml").string();
  std::ofstream(bs) << "timeline:\n  - {t: 0.2, fire: gun}\n  - {t: 0.1, fire: gun}\n";
  r = test::run_cli("run " + scene + " --script " + bs + " --headless");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(bs + ":3:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("time goes backwards"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "never.rec"));
}

}  // namespace
}  // namespace ps
