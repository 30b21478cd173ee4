// The template on the trainee window's TRUS image (app/gui/trainee_window.cpp, issue 46 item 1),
// clicked under a virtual X server (xvfb-run): the test hook PROSTATESIM_CLICKS="hole C3.5" moves
// the mouse of a user onto hole C3.5 where the transverse image shows it, presses and releases,
// so the image's own click code picks the hole: the plan's needle of that hole becomes the active
// one and is aimed along it. Skipped without xvfb-run or without the window in the build.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

#include "tests/app/run_cli.h"
#include "tests/xvfb.h"

namespace ps {
namespace {

namespace fs = std::filesystem;

TEST(WindowTemplate, AClickOnAHoleOfTheTransverseImageAimsThatHolesNeedle) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const fs::path dir = test::cli_temp_dir("window_template");
  const fs::path log = dir / "log.txt", png = dir / "window.png";
  const std::string cmd = "cd " + dir.string() + " && PROSTATESIM_CLICKS='hole C3.5' PROSTATESIM_SCREENSHOT=" + png.string() +
                          " timeout 240 " + test::xvfb_run((dir / "Xauthority").string()) + PROSTATESIM_BINARY " run " +
                          PROSTATESIM_SOURCE_DIR "/config/brachytherapy_plan.yaml --duration 0.5 --unpaced > " + log.string() + " 2>&1";
  const int st = std::system(cmd.c_str());
  const std::string out = test::read_text(log);
  if (out.find("headless") != std::string::npos) GTEST_SKIP() << "built without the window";
  ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << out;
  EXPECT_NE(out.find("click: hole C3.5"), std::string::npos) << out;
  // C3.5 is the plan's 7th needle, named after its hole (config/brachytherapy_plan_145gy.yaml)
  EXPECT_NE(out.find("picked hole C3.5: needle 'C3.5' aimed along it"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(png));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ps
