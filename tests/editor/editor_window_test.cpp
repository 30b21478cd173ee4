// The editor window (app/editor/editor_window.cpp) under a virtual X server (xvfb-run): it opens
// the biopsy scene, applies an edit through the command path and saves it (one line of the file
// changes, comments kept), shows the panels and the prostate; a refused edit exits 2 leaving the
// file intact; a file broken by hand opens with its error shown, not a crash.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "tests/app/run_cli.h"
#include "tests/xvfb.h"

namespace {

namespace fs = std::filesystem;

using ps::test::read_text;  // tests/app/run_cli.h

struct Shot {
  int w = 0, h = 0;
  std::vector<unsigned char> px;
  int count(int x0, int x1, bool (*pred)(const unsigned char*)) const {
    int c = 0;
    for (int y = 0; y < h; ++y)
      for (int x = x0; x < x1; ++x) c += pred(&px[3 * (static_cast<size_t>(y) * w + x)]);
    return c;
  }
};

Shot load(const std::string& png) {
  Shot s;
  int n = 0;
  unsigned char* img = stbi_load(png.c_str(), &s.w, &s.h, &n, 3);
  if (!img) return s;
  s.px.assign(img, img + 3 * static_cast<size_t>(s.w) * s.h);
  stbi_image_free(img);
  return s;
}

class EditorWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!PROSTATESIM_GUI_BUILD) GTEST_SKIP() << "built without the GUI";
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
    dir_ = fs::temp_directory_path() / ("ps_editor_window_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "config");
    // the scene refers to ../assets/anatomy: the copy sits beside a link to the real assets
    fs::create_directory_symlink(fs::path(PROSTATESIM_SOURCE_DIR) / "assets", dir_ / "assets");
    file_ = dir_ / "config" / "biopsy.yaml";
    fs::copy_file(fs::path(PROSTATESIM_SOURCE_DIR) / "config" / "biopsy.yaml", file_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  int edit(const std::string& args, const std::string& png) {
    const std::string cmd = ps::test::xvfb_run((dir_ / "Xauthority").string()) + PROSTATESIM_BINARY " edit " + file_.string() + " " + args +
                            " --frames 4 --screenshot " + png + " > " + (dir_ / "log.txt").string() + " 2>&1";
    const int st = std::system(cmd.c_str());
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  }
  std::string log() const { return read_text(dir_ / "log.txt"); }
  fs::path dir_, file_;
};

TEST_F(EditorWindow, OpensAppliesAnEditAndSaves) {
  const std::string before = read_text(file_), png = (dir_ / "edit.png").string();
  ASSERT_EQ(edit("--set materials.prostate.young_kpa=45 --save", png), 0) << log();
  const std::string after = read_text(file_);
  std::string expected = before;
  const std::string from = "prostate: {model: tet, young_kpa: 40,", to = "prostate: {model: tet, young_kpa: 45,";
  ASSERT_NE(expected.find(from), std::string::npos);
  expected.replace(expected.find(from), from.size(), to);
  EXPECT_EQ(after, expected) << "only the edited value changes: key order and comments kept";
  EXPECT_NE(log().find("model hash"), std::string::npos) << log();
  const Shot s = load(png);
  ASSERT_EQ(s.w, 1600) << log();
  ASSERT_EQ(s.h, 900);
  auto bright = [](const unsigned char* p) { return p[0] > 180 && p[1] > 180 && p[2] > 180; };
  auto pink = [](const unsigned char* p) { return p[0] > p[1] + 30 && p[0] > p[2] + 30; };
  EXPECT_GT(s.count(0, 440, bright), 3000) << "no text in the editing panel";
  EXPECT_GT(s.count(440, 1600, pink), 5000) << "no prostate in the 3D view";
}

// The preview runs the edited text in place: its state after 0.03 s is bit for bit the state of
// `prostatesim run --headless --unpaced` on the saved file.
TEST_F(EditorWindow, PreviewRunsTheEditedSceneAsTheSimulationDoes) {
  const std::string png = (dir_ / "preview.png").string();
  ASSERT_EQ(edit("--set materials.prostate.young_kpa=45 --save --preview 0.03", png), 0) << log();
  std::smatch m;
  const std::string l = log();
  ASSERT_TRUE(std::regex_search(l, m, std::regex("preview: [0-9]+ ticks, t = 0.03 s, state hash ([0-9a-f]{16})"))) << l;
  const auto run = ps::test::run_cli("run " + file_.string() + " --headless --unpaced --duration 0.03 --hash");
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find(m[1].str()), std::string::npos) << "preview " << m[1] << ", run: " << run.out;
  // and not the state of the file before the edit
  const auto orig = ps::test::run_cli("run " + std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml --headless --unpaced --duration 0.03 --hash");
  EXPECT_EQ(orig.out.find(m[1].str()), std::string::npos) << orig.out;
}

TEST_F(EditorWindow, RefusedEditExits2AndLeavesTheFile) {
  const std::string before = read_text(file_);
  EXPECT_EQ(edit("--set materials.prostate.young_kpa=-40 --save", (dir_ / "r.png").string()), 2) << log();
  EXPECT_EQ(read_text(file_), before);
  EXPECT_NE(log().find("materials.prostate.young_kpa"), std::string::npos) << log();
}

TEST_F(EditorWindow, HandBrokenFileOpensWithItsError) {
  std::string t = read_text(file_);
  t.replace(t.find("young_kpa: 40"), 13, "young_kpa: -4");
  std::ofstream(file_) << t;
  const std::string png = (dir_ / "broken.png").string();
  ASSERT_EQ(edit("", png), 0) << log();
  EXPECT_NE(log().find("young_kpa"), std::string::npos) << log();
  const Shot s = load(png);
  ASSERT_EQ(s.w, 1600) << log();
  auto red = [](const unsigned char* p) { return p[0] > 200 && p[1] < 140 && p[2] < 140; };
  EXPECT_GT(s.count(0, 440, red), 300) << "the error is shown in the panel";
}

}  // namespace
