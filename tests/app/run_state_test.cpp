// `prostatesim run/replay --state FILE` (app/cmd_run.cpp, app/cmd_replay.cpp): the last good
// state written by --save-on-fault at tick 150, loaded by `replay --state` and by `run --state`
// and run on to 0.3 s, ends in the state hash of a run that never faulted; a state of an edited
// scenario file or a damaged one exits 2 naming file:line:field and writes nothing; --state with
// --record is refused before the recording is created.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "tests/app/run_cli.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

std::string last_hash(const std::string& out) {
  std::string h;
  const std::regex re("\\b([0-9a-f]{16})\\b");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), re); it != std::sregex_iterator(); ++it)
    h = (*it)[1].str();
  return h;
}

TEST(RunState, ALastGoodStateLoadedWithStateRunsOnToTheCleanHash) {
  const auto dir = test::cli_temp_dir("run_state");
  const std::string scene = test::write_live_scene(dir.string());
  const std::string script = (dir / "live.yaml").string();
  std::ofstream(script) << test::live_script_yaml();
  const std::string good = (dir / "good.state").string();
  const auto f = test::run_cli("run " + scene + " --script " + script + " --headless --duration 0.3 --unpaced --inject-fault nan@150 --save-on-fault " + good);
  ASSERT_EQ(f.code, 3) << f.out;
  ASSERT_TRUE(std::filesystem::exists(good)) << f.out;

  const auto clean = test::run_cli("replay " + scene + " --script " + script + " --duration 0.3 --hash");
  ASSERT_EQ(clean.code, 0) << clean.out;
  const std::string h = last_hash(clean.out);
  ASSERT_EQ(h.size(), 16u) << clean.out;

  const auto rep = test::run_cli("replay " + scene + " --script " + script + " --state " + good + " --duration 0.3");
  ASSERT_EQ(rep.code, 0) << rep.out;
  EXPECT_NE(rep.out.find("loaded " + good + ": tick 150"), std::string::npos) << rep.out;
  EXPECT_NE(rep.out.find("replayed 300 ticks"), std::string::npos) << rep.out;
  EXPECT_EQ(last_hash(rep.out), h) << rep.out;

  const auto live = test::run_cli("run " + scene + " --script " + script + " --state " + good + " --headless --duration 0.3 --unpaced --hash");
  ASSERT_EQ(live.code, 0) << live.out;
  EXPECT_EQ(last_hash(live.out), h) << live.out;
  std::printf("clean run to 0.3 s: %s; loaded at tick 150 and run on: replay %s, run %s\n", h.c_str(), last_hash(rep.out).c_str(),
              last_hash(live.out).c_str());
}

TEST(RunState, AForeignOrDamagedStateIsBadInputNamingFileLineAndField) {
  const auto dir = test::cli_temp_dir("run_state_bad");
  const std::string scene = test::write_live_scene(dir.string());
  const std::string script = (dir / "live.yaml").string();
  std::ofstream(script) << test::live_script_yaml();
  const std::string good = (dir / "good.state").string();
  ASSERT_EQ(test::run_cli("run " + scene + " --script " + script + " --headless --duration 0.2 --unpaced --inject-fault nan@100 --save-on-fault " + good).code, 3);
  // the same scene with one comment more: another file content, so another scenario for a state
  const std::string edited = (dir / "edited.yaml").string();
  std::ofstream(edited) << test::read_text(scene) << "# edited\n";
  const auto r = test::run_cli("replay " + edited + " --script " + script + " --state " + good + " --duration 0.2 --hash");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(good + ":4: 'scenario_hash'"), std::string::npos) << r.out;
  // damaged bytes
  std::string text = test::read_text(good);
  text[text.size() - 5] ^= 0x21;
  const std::string damaged = (dir / "damaged.state").string();
  std::ofstream(damaged, std::ios::binary) << text;
  const auto d = test::run_cli("run " + scene + " --script " + script + " --state " + damaged + " --headless --duration 0.2 --unpaced");
  EXPECT_EQ(d.code, 2) << d.out;
  EXPECT_NE(d.out.find(damaged + ":7: 'state_hash'"), std::string::npos) << d.out;
  // not with --record: refused before the recording file exists
  const std::string rec = (dir / "x.rec").string();
  const auto w = test::run_cli("run " + scene + " --state " + good + " --headless --duration 0.2 --unpaced --record " + rec);
  EXPECT_EQ(w.code, 2) << w.out;
  EXPECT_NE(w.out.find("'--state'"), std::string::npos) << w.out;
  EXPECT_FALSE(std::filesystem::exists(rec));
}

}  // namespace
}  // namespace ps
