// `prostatesim replay ... --out DIR`: numbered PNG frames, event log, summary and contact sheet;
// the same command twice gives byte-identical frames; bad options are refused with exit 2 and
// nothing written.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string tmp(const std::string& name) {
  return (fs::temp_directory_path() / ("prostatesim_replay_" + std::to_string(::getpid()) + "_" + name)).string();
}

int replay(const std::string& args) {
  const std::string cmd = std::string("cd " PROSTATESIM_SOURCE_DIR " && " PROSTATESIM_BINARY
                                      " replay config/biopsy.yaml --script config/scripts/biopsy.yaml --duration 0.02 ") +
                          args + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(ReplayFrames, WritesFramesLogSummaryAndSheetIdenticallyTwice) {
  const std::string a = tmp("a"), b = tmp("b");
  fs::remove_all(a);
  fs::remove_all(b);
  const std::string opts = " --size 160x90 --fps 100 --views 3d,lateral";
  ASSERT_EQ(replay("--out " + a + opts), 0);
  ASSERT_EQ(replay("--out " + b + opts), 0);
  // 20 ticks at a frame every 10 ticks: frames at ticks 0, 10, 20
  for (const char* v : {"3d", "lateral"})
    for (int f = 0; f < 3; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06d.png", f);
      const fs::path pa = fs::path(a) / v / name, pb = fs::path(b) / v / name;
      ASSERT_TRUE(fs::exists(pa)) << pa;
      EXPECT_GT(fs::file_size(pa), 1000u);
      EXPECT_EQ(bytes(pa), bytes(pb)) << "frame differs between runs: " << pa;
    }
  EXPECT_FALSE(fs::exists(fs::path(a) / "3d" / "frame_000003.png"));
  for (const char* f : {"events.log", "summary.json", "force_depth.csv", "contact_sheet.png"})
    EXPECT_TRUE(fs::exists(fs::path(a) / f)) << f;
  EXPECT_NE(bytes(fs::path(a) / "summary.json").find("\"frames_per_view\": 3"), std::string::npos);
  // a second run into the same folder is refused without --force, accepted with it
  EXPECT_EQ(replay("--out " + a + opts), 2);
  EXPECT_EQ(replay("--out " + a + opts + " --force"), 0);
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(ReplayFrames, BadOptionsExit2AndWriteNothing) {
  const std::string d = tmp("bad");
  fs::remove_all(d);
  EXPECT_EQ(replay("--out " + d + " --size 0x0"), 2);
  EXPECT_EQ(replay("--out " + d + " --size 100000x100000"), 2);
  EXPECT_EQ(replay("--out " + d + " --views 3d,top"), 2);
  EXPECT_EQ(replay("--out " + d + " --fps 0"), 2);
  EXPECT_FALSE(fs::exists(d));
  // no EGL and no OSMesa: one message, exit 2, the folder not even created
  const std::string cmd = std::string("cd " PROSTATESIM_SOURCE_DIR " && PROSTATESIM_EGL_LIB=/nonexistent PROSTATESIM_OSMESA_LIB=/nonexistent " PROSTATESIM_BINARY
                                      " replay config/biopsy.yaml --script config/scripts/biopsy.yaml --duration 0.01 --out ") + d + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_FALSE(fs::exists(d));
  // an output folder that cannot be created
  EXPECT_EQ(replay("--out /proc/prostatesim_cannot_write"), 2);
}

}  // namespace
