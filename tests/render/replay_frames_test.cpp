// `prostatesim replay ... --out DIR`: numbered PNG frames, event log, summary and contact sheet;
// the same command twice gives byte-identical frames; bad options are refused with exit 2 and
// nothing written. The simulated ultrasound views write grayscale frames, deterministic too.
#include <gtest/gtest.h>

#include <map>
#include <stb_image.h>

#include <cmath>
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
  const std::string summary = bytes(fs::path(a) / "summary.json");
  EXPECT_NE(summary.find("\"frames_per_view\": 3"), std::string::npos);
  // --aa auto: FXAA on the encoder thread on a software rasteriser, 4x multisampling otherwise
  const bool software = summary.find("llvmpipe") != std::string::npos || summary.find("softpipe") != std::string::npos;
  EXPECT_NE(summary.find(software ? "\"antialias\": \"fxaa\"" : "\"antialias\": \"msaa\""), std::string::npos) << summary;
  // a second run into the same folder is refused without --force, accepted with it
  EXPECT_EQ(replay("--out " + a + opts), 2);
  EXPECT_EQ(replay("--out " + a + opts + " --force"), 0);
  fs::remove_all(a);
  fs::remove_all(b);
}

// The contact sheet's plot shows what the scene's instruments did: the needle's force against
// depth, or without a needle the filling's volume (or the probe's force) against time, and no plot
// in a scene without instruments (an empty "no needle" chart was drawn there before).
TEST(ReplayFrames, TheContactSheetPlotsWhatTheScenesInstrumentsDid) {
  auto sheet_size = [](const std::string& scene, const std::string& name, double duration, int& w, int& h) {
    const std::string dir = tmp(name);
    fs::remove_all(dir);
    const std::string script = dir + "_script.yaml";
    std::ofstream(script) << "scenario: " << name << "\nduration_s: " << duration << "\ntimeline: []\n";
    const std::string cmd = std::string("cd " PROSTATESIM_SOURCE_DIR " && " PROSTATESIM_BINARY " replay ") + scene + " --script " +
                            script + " --out " + dir + " --size 160x90 --fps 5 --views lateral > /dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << cmd;
    int n = 0;
    ASSERT_TRUE(stbi_info((fs::path(dir) / "contact_sheet.png").string().c_str(), &w, &h, &n));
    fs::remove_all(dir);
    fs::remove(script);
  };
  int fw = 0, fh = 0, cw = 0, ch = 0;
  sheet_size("config/bladder_filling.yaml", "bladder_filling", 0.8, fw, fh);  // the filling starts at 0.5 s
  sheet_size("config/validation/cube_bonded.yaml", "cube_bonded", 0.8, cw, ch);
  // two rows of two 160 x 90 frames with their captions (30 px) and 8 px padding; the plot 480 + 8
  EXPECT_EQ(ch, 2 * (90 + 22 + 8) + 8);
  EXPECT_EQ(fh, ch + 480 + 8);
  EXPECT_EQ(fw, cw);
}

// Issue 12 item 3: `--views us_transverse,us_sagittal` writes the simulated TRUS of every frame
// (512 x 512 grayscale), byte-identical on two runs, and different frames differ only where the
// scene moved (the probe is being placed: the images change between the first and last frame).
TEST(ReplayFrames, UltrasoundViewsWriteGrayscaleFramesIdenticallyTwice) {
  const std::string a = tmp("usa"), b = tmp("usb");
  fs::remove_all(a);
  fs::remove_all(b);
  const std::string opts = " --size 160x90 --fps 100 --views us_transverse,3d,us_sagittal";
  ASSERT_EQ(replay("--out " + a + opts), 0);
  ASSERT_EQ(replay("--out " + b + opts), 0);
  for (const char* v : {"us_transverse", "us_sagittal"}) {
    for (int f = 0; f < 3; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06d.png", f);
      const fs::path pa = fs::path(a) / v / name, pb = fs::path(b) / v / name;
      ASSERT_TRUE(fs::exists(pa)) << pa;
      int w = 0, h = 0, n = 0;
      ASSERT_TRUE(stbi_info(pa.string().c_str(), &w, &h, &n)) << pa;
      EXPECT_EQ(w, 512);
      EXPECT_EQ(h, 512);
      EXPECT_EQ(n, 1) << "grayscale";
      unsigned char* img = stbi_load(pa.string().c_str(), &w, &h, &n, 1);
      ASSERT_NE(img, nullptr);
      long lit = 0;
      for (int i = 0; i < w * h; ++i) lit += img[i] > 40;
      stbi_image_free(img);
      EXPECT_GT(lit, w * h / 5) << pa << ": the tissue in view should be imaged";
      EXPECT_EQ(bytes(pa), bytes(pb)) << "ultrasound frame differs between runs: " << pa;
    }
    EXPECT_NE(bytes(fs::path(a) / v / "frame_000000.png"), bytes(fs::path(a) / v / "frame_000002.png"))
        << v << ": the probe moves during these frames, the image must follow";
  }
  const std::string summary = bytes(fs::path(a) / "summary.json");
  EXPECT_NE(summary.find("\"us_sagittal\""), std::string::npos);
  EXPECT_NE(summary.find("ultrasound_ms_median"), std::string::npos);
  fs::remove_all(a);
  fs::remove_all(b);
}

// The OSMesa fallback (PROSTATESIM_GL=osmesa) draws the same scene as EGL: both are Mesa's
// software rasteriser behind a different window-system layer, so the frames must agree to within
// antialiasing noise. Stated tolerance: mean |difference| <= 1 level and >= 99 % of the channel
// values within 8 levels (measured: identical bytes here).
TEST(ReplayFrames, OsmesaFallbackRendersTheSameSceneAsEgl) {
  const std::string e = tmp("egl"), o = tmp("osmesa");
  fs::remove_all(e);
  fs::remove_all(o);
  const std::string opts = " --size 320x180 --fps 100 --views lateral";
  ASSERT_EQ(replay("--out " + e + opts), 0);
  const std::string cmd = std::string("cd " PROSTATESIM_SOURCE_DIR " && PROSTATESIM_GL=osmesa " PROSTATESIM_BINARY
                                      " replay config/biopsy.yaml --script config/scripts/biopsy.yaml --duration 0.02 --out ") +
                          o + opts + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  ASSERT_EQ(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, 0) << cmd;
  EXPECT_NE(bytes(fs::path(o) / "summary.json").find("\"gl_backend\": \"osmesa\""), std::string::npos);
  EXPECT_NE(bytes(fs::path(e) / "summary.json").find("\"gl_backend\": \"egl\""), std::string::npos);
  for (int f = 0; f < 3; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", f);
    int w1 = 0, h1 = 0, w2 = 0, h2 = 0, n = 0;
    unsigned char* a = stbi_load((fs::path(e) / "lateral" / name).string().c_str(), &w1, &h1, &n, 3);
    unsigned char* b = stbi_load((fs::path(o) / "lateral" / name).string().c_str(), &w2, &h2, &n, 3);
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    ASSERT_EQ(w1, w2);
    ASSERT_EQ(h1, h2);
    const long values = 3L * w1 * h1;
    long sum = 0, within = 0, pink = 0;
    for (long i = 0; i < values; ++i) {
      const int d = std::abs(int(a[i]) - int(b[i]));
      sum += d;
      within += d <= 8;
    }
    for (long i = 0; i < values; i += 3) pink += b[i] > b[i + 1] + 30 && b[i] > b[i + 2] + 30;
    std::printf("frame %d: mean |egl - osmesa| %.4f, within 8 levels %.4f %%, prostate pixels %ld\n", f,
                double(sum) / values, 100.0 * within / values, pink);
    EXPECT_LE(double(sum) / values, 1.0);
    EXPECT_GE(double(within) / values, 0.99);
    EXPECT_GT(pink, 500) << "the OSMesa frame shows no prostate";
    stbi_image_free(a);
    stbi_image_free(b);
  }
  fs::remove_all(e);
  fs::remove_all(o);
}

// --aa: each mode renders the same scene; FXAA changes only pixels on edges (on or next to a
// pixel whose colour steps from a neighbour's) and brings the frame closer to a 16x supersampled one (the same scene drawn at 4x
// the size without antialiasing, box-filtered down), outside the text overlay.
TEST(ReplayFrames, AntialiasModesRenderTheSameSceneAndFxaaApproachesSupersampling) {
  std::map<std::string, std::vector<unsigned char>> img;
  int w = 0, h = 0, n = 0;
  for (const char* mode : {"none", "fxaa", "msaa", "reference"}) {
    const std::string d = tmp(std::string("aa_") + mode);
    fs::remove_all(d);
    const bool ref = std::string(mode) == "reference";
    ASSERT_EQ(replay("--out " + d + (ref ? " --size 1280x720" : " --size 320x180") + " --fps 100 --views 3d --aa " +
                     (ref ? "none" : mode)),
              0)
        << mode;
    if (ref) {
      int rw = 0, rh = 0;
      unsigned char* p = stbi_load((fs::path(d) / "3d" / "frame_000002.png").string().c_str(), &rw, &rh, &n, 3);
      ASSERT_NE(p, nullptr);
      ASSERT_EQ(rw, 4 * w);
      std::vector<unsigned char>& r = img[mode];
      r.assign(3L * w * h, 0);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int k = 0; k < 3; ++k) {
            int sum = 0;
            for (int j = 0; j < 4; ++j)
              for (int i = 0; i < 4; ++i) sum += p[3L * ((4 * y + j) * rw + 4 * x + i) + k];
            r[3L * (y * w + x) + k] = static_cast<unsigned char>((sum + 8) / 16);
          }
      stbi_image_free(p);
      fs::remove_all(d);
      continue;
    }
    EXPECT_NE(bytes(fs::path(d) / "summary.json").find(std::string("\"antialias\": \"") + mode + "\""), std::string::npos);
    unsigned char* p = stbi_load((fs::path(d) / "3d" / "frame_000002.png").string().c_str(), &w, &h, &n, 3);
    ASSERT_NE(p, nullptr) << mode;
    img[mode].assign(p, p + 3L * w * h);
    stbi_image_free(p);
    fs::remove_all(d);
  }
  const long px = static_cast<long>(w) * h;
  auto changed = [&](const std::string& a, const std::string& b) {
    long c = 0;
    for (long i = 0; i < px; ++i)
      c += img[a][3 * i] != img[b][3 * i] || img[a][3 * i + 1] != img[b][3 * i + 1] || img[a][3 * i + 2] != img[b][3 * i + 2];
    return c;
  };
  auto mean_abs = [&](const std::string& a, const std::string& b) {
    double s = 0.0;
    for (long i = 0; i < 3 * px; ++i) s += std::abs(int(img[a][i]) - int(img[b][i]));
    return s / (3.0 * px);
  };
  const long fx = changed("none", "fxaa");
  std::printf("fxaa changed %ld of %ld px; mean |none - msaa| %.3f, |fxaa - msaa| %.3f\n", fx, px,
              mean_abs("none", "msaa"), mean_abs("fxaa", "msaa"));
  EXPECT_GT(fx, px / 200);  // it ran: the organ outlines are edges
  // and only there: every changed pixel lies on an edge of the plain frame (a channel differing by
  // 8 or more from a 4-neighbour: half FXAA's own minimum contrast of 16) or next to one
  std::vector<uint8_t> edge(px, 0);
  const std::vector<unsigned char>& a0 = img["none"];
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const long i = static_cast<long>(y) * w + x;
      bool e = false;
      for (long j : {i - 1, i + 1, i - w, i + w})
        for (int k = 0; k < 3; ++k) e = e || std::abs(int(a0[3 * i + k]) - int(a0[3 * j + k])) >= 8;
      if (e)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) edge[i + dy * w + dx] = 1;
    }
  long off_edge = 0, on_edge = 0;
  for (long i = 0; i < px; ++i) {
    on_edge += edge[i];
    off_edge += !edge[i] && (img["none"][3 * i] != img["fxaa"][3 * i] || img["none"][3 * i + 1] != img["fxaa"][3 * i + 1] ||
                             img["none"][3 * i + 2] != img["fxaa"][3 * i + 2]);
  }
  std::printf("fxaa: %ld changed pixels off the edges (%ld px on or next to edges)\n", off_edge, on_edge);
  EXPECT_LT(off_edge, px / 1000);
  // the same scene in every mode: the frames differ by edge noise only
  EXPECT_LT(mean_abs("none", "msaa"), 2.0);
  EXPECT_LT(mean_abs("fxaa", "msaa"), 2.0);
  // RMS against the supersampled frame, the text overlay left out (its font is drawn at another
  // scale at 1280x720): top bar and read-out (y < 32), legend (x < 80, y > h - 70)
  auto rms_ref = [&](const std::string& a) {
    double s = 0.0;
    long c = 0;
    for (int y = 32; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (x < 80 && y > h - 70) continue;
        for (int k = 0; k < 3; ++k) {
          const double d = double(img[a][3L * (y * w + x) + k]) - img["reference"][3L * (y * w + x) + k];
          s += d * d;
          ++c;
        }
      }
    return std::sqrt(s / c);
  };
  std::printf("RMS against 16x supersampling: none %.2f, fxaa %.2f, msaa %.2f grey levels\n", rms_ref("none"),
              rms_ref("fxaa"), rms_ref("msaa"));
  EXPECT_LT(rms_ref("fxaa"), 0.9 * rms_ref("none"));
}

TEST(ReplayFrames, BadOptionsExit2AndWriteNothing) {
  const std::string d = tmp("bad");
  fs::remove_all(d);
  EXPECT_EQ(replay("--out " + d + " --size 0x0"), 2);
  EXPECT_EQ(replay("--out " + d + " --size 100000x100000"), 2);
  EXPECT_EQ(replay("--out " + d + " --views 3d,top"), 2);
  EXPECT_EQ(replay("--out " + d + " --fps 0"), 2);
  EXPECT_EQ(replay("--out " + d + " --views us_coronal"), 2);
  EXPECT_EQ(replay("--out " + d + " --views us_sagittal,us_sagittal"), 2);
  EXPECT_EQ(replay("--out " + d + " --aa smaa"), 2);
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

// Issue 46: in a scene with seeds the ultrasound frames are RGB, and once seeds are in, the
// isodose lines are drawn on the plane that crosses their dose (the shipped brachytherapy script:
// four seeds drop by 6.25 s, along the `posterior` needle 5 mm beside the sagittal plane, which
// cuts their 50 % isodose; colours app/frames/us_isodose.h). Before the first seed: no line.
TEST(ReplayFrames, UltrasoundOfAnImplantShowsTheIsodoseLinesOnceSeedsAreIn) {
  const std::string a = tmp("iso");
  fs::remove_all(a);
  const std::string cmd = std::string("cd " PROSTATESIM_SOURCE_DIR " && " PROSTATESIM_BINARY
                                      " replay config/brachytherapy.yaml --script config/scripts/brachytherapy.yaml --out ") +
                          a + " --fps 1 --views us_sagittal > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  auto count = [&](const char* frame, int r, int g, int b) {
    const fs::path p = fs::path(a) / "us_sagittal" / frame;
    int w = 0, h = 0, n = 0;
    EXPECT_TRUE(stbi_info(p.string().c_str(), &w, &h, &n)) << p;
    EXPECT_EQ(n, 3) << p << ": RGB in a scene with seeds";
    unsigned char* img = stbi_load(p.string().c_str(), &w, &h, &n, 3);
    if (!img) return -1L;
    long k = 0;
    for (int i = 0; i < w * h; ++i) k += img[3 * i] == r && img[3 * i + 1] == g && img[3 * i + 2] == b;
    stbi_image_free(img);
    return k;
  };
  EXPECT_EQ(count("frame_000000.png", 70, 150, 255), 0) << "no seed yet: no isodose line";
  EXPECT_GT(count("frame_000006.png", 70, 150, 255), 200) << "the 50 % line around the four seeds (t = 6 s)";
  fs::remove_all(a);
}

}  // namespace
