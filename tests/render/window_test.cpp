// The trainee window opens under a virtual X server (xvfb-run), runs frames of the biopsy scene
// and its screenshot (PROSTATESIM_SCREENSHOT, panels included) is non-empty and shows the panels:
// text in the left (instruments) and right (read-outs) panels and the pink prostate in the 3D
// view between them, and the live biplane ultrasound images (speckle) in the right panel.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/xvfb.h"

namespace {

TEST(TraineeWindow, OpensUnderXvfbAndShowsThePanels) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const std::string png = (std::filesystem::temp_directory_path() / ("prostatesim_window_" + std::to_string(::getpid()) + ".png")).string();
  std::filesystem::remove(png);
  const std::string auth = png + ".Xauthority";
  const std::string cmd = "cd " PROSTATESIM_SOURCE_DIR " && PROSTATESIM_SCREENSHOT=" + png +
                          " " + ps::test::xvfb_run(auth) + PROSTATESIM_BINARY
                          " run config/biopsy.yaml --script config/scripts/biopsy.yaml --duration 0.05 > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  std::filesystem::remove(auth);
  ASSERT_EQ(rc, 0) << cmd;
  int w = 0, h = 0, n = 0;
  unsigned char* img = stbi_load(png.c_str(), &w, &h, &n, 3);
  ASSERT_NE(img, nullptr) << "no screenshot at " << png;
  EXPECT_EQ(w, 1600);
  EXPECT_EQ(h, 900);
  auto count = [&](int x0, int x1, auto pred) {
    int c = 0;
    for (int y = 0; y < h; ++y)
      for (int x = x0; x < x1; ++x) c += pred(&img[3 * (static_cast<size_t>(y) * w + x)]);
    return c;
  };
  auto bright = [](const unsigned char* p) { return p[0] > 180 && p[1] > 180 && p[2] > 180; };
  auto pink = [](const unsigned char* p) { return p[0] > p[1] + 30 && p[0] > p[2] + 30; };
  EXPECT_GT(count(0, 330, bright), 1500) << "no text in the instruments panel";
  EXPECT_GT(count(w - 400, w, bright), 1500) << "no text in the read-outs panel";
  EXPECT_GT(count(330, w - 400, pink), 5000) << "no prostate in the 3D view";
  // the live biplane ultrasound (right panel): speckle = many mid-gray pixels, none of ImGui's
  // dark panel or blue header colours, and neighbours that differ (texture, not a flat fill)
  int gray = 0, textured = 0;
  for (int y = 0; y + 1 < h; ++y)
    for (int x = w - 400; x + 1 < w; ++x) {
      const unsigned char* p = &img[3 * (static_cast<size_t>(y) * w + x)];
      if (std::abs(p[0] - p[1]) > 3 || std::abs(p[1] - p[2]) > 3 || p[0] < 40 || p[0] > 230) continue;
      ++gray;
      textured += std::abs(p[0] - p[3]) > 12 || std::abs(p[0] - p[3 * w]) > 12;
    }
  std::printf("right panel: %d mid-gray pixels, %d of them differ from a neighbour by > 12\n", gray, textured);
  EXPECT_GT(gray, 20000) << "no ultrasound image in the read-outs panel";
  EXPECT_GT(textured, 8000) << "the ultrasound panel shows no speckle";
  stbi_image_free(img);
  std::filesystem::remove(png);
}

}  // namespace
