// The trainee window's fault recovery (app/gui/trainee_window.cpp, issue 14), clicked under a
// virtual X server (xvfb-run): a NaN injected before tick 100 stops the physics; the test hook
// PROSTATESIM_CLICKS feeds ImGui a user's mouse (onto the button, press, release) to click
// "Save last good state" (the file holds the state after 100 ticks: the hash of a clean replay
// to 0.1 s) and then "Restart scene" (the scene runs again from the start to the end: the clean
// run's final hash) or "Load state" (the saved state loaded in the live window: it runs on from
// tick 100 to the same final hash). Skipped without xvfb-run or without the window in the build.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>

#include "tests/app/run_cli.h"
#include "tests/engine/realtime/live_scene.h"
#include "tests/xvfb.h"

namespace ps {
namespace {

namespace fs = std::filesystem;

// the 16 hex digits after the last `prefix` in `out` ("" none)
std::string hash_after(const std::string& out, const std::string& prefix) {
  std::string h;
  const std::regex re(prefix + "([0-9a-f]{16})");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), re); it != std::sregex_iterator(); ++it) h = (*it)[1].str();
  return h;
}

class WindowRecovery : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
    dir_ = test::cli_temp_dir("window_recovery");
    scene_ = test::write_live_scene(dir_.string());
    script_ = (dir_ / "live.yaml").string();
    std::ofstream(script_) << test::live_script_yaml();
    const auto clean = test::run_cli("replay " + scene_ + " --script " + script_ + " --duration 0.3 --hash");
    ASSERT_EQ(clean.code, 0) << clean.out;
    clean_end_ = hash_after(clean.out, "");
    const auto at100 = test::run_cli("replay " + scene_ + " --script " + script_ + " --duration 0.1 --hash");
    ASSERT_EQ(at100.code, 0) << at100.out;
    clean_100_ = hash_after(at100.out, "");
  }
  // Runs the window in dir_ (the saved state lands there), clicking `clicks`; returns the exit code.
  int window(const std::string& clicks, const std::string& png) {
    const std::string cmd = "cd " + dir_.string() + " && PROSTATESIM_CLICKS='" + clicks + "' PROSTATESIM_SCREENSHOT=" + png +
                            " timeout 240 " + test::xvfb_run((dir_ / "Xauthority").string()) + PROSTATESIM_BINARY " run " + scene_ + " --script " +
                            script_ + " --duration 0.3 --unpaced --inject-fault nan@100 > " + (dir_ / "log.txt").string() + " 2>&1";
    const int st = std::system(cmd.c_str());
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  }
  std::string log() const { return test::read_text(dir_ / "log.txt"); }
  fs::path dir_;
  std::string scene_, script_, clean_end_, clean_100_;
};

TEST_F(WindowRecovery, SaveLastGoodStateThenRestartScene) {
  const int rc = window("Save last good state;Restart scene", (dir_ / "restart.png").string());
  const std::string out = log();
  if (out.find("headless") != std::string::npos) GTEST_SKIP() << "built without the window";
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("click: Save last good state"), std::string::npos) << out;
  EXPECT_NE(out.find("click: Restart scene"), std::string::npos) << out;
  EXPECT_NE(out.find("restarted after a fault"), std::string::npos) << out;
  const fs::path saved = dir_ / "live_box-tick100.state";
  ASSERT_TRUE(fs::exists(saved)) << out;
  EXPECT_EQ(hash_after(test::read_text(saved), "\nstate_hash "), clean_100_) << "the saved state is not the state after 100 ticks";
  EXPECT_EQ(hash_after(out, "state hash "), clean_end_) << "after the restart the scene did not run clean to the end\n" << out;
  EXPECT_TRUE(fs::exists(dir_ / "restart.png"));
}

TEST_F(WindowRecovery, SaveLastGoodStateThenLoadIt) {
  const int rc = window("Save last good state;Load state", (dir_ / "load.png").string());
  const std::string out = log();
  if (out.find("headless") != std::string::npos) GTEST_SKIP() << "built without the window";
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("click: Load state"), std::string::npos) << out;
  EXPECT_NE(out.find("loaded state live_box-tick100.state: tick 100, state hash " + clean_100_), std::string::npos) << out;
  EXPECT_EQ(out.find("restarted"), std::string::npos) << out;
  EXPECT_EQ(hash_after(out, "state hash "), clean_end_) << "the loaded state did not run on to the clean run's end\n" << out;
}

}  // namespace
}  // namespace ps
