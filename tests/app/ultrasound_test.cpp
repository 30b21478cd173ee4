// `prostatesim ultrasound` as a user runs it (app/cmd_ultrasound.cpp): both planes as PNG from the
// biopsy scene; nonsensical scanner settings or views exit 2 naming the field, writing nothing.
#include <gtest/gtest.h>

#include <filesystem>

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "tests/app/run_cli.h"

namespace {

namespace fs = std::filesystem;
using ps::test::run_cli;

const std::string kScene = std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml";

TEST(CliUltrasound, WritesBothPlanesAsPng) {
  const fs::path out = ps::test::cli_temp_dir("ultrasound_ok");
  const auto r = run_cli("ultrasound " + kScene + " --out " + out.string() + " --time 0.01 --size 160");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* v : {"us_transverse.png", "us_sagittal.png"}) {
    int w = 0, h = 0, c = 0;
    unsigned char* px = stbi_load((out / v).string().c_str(), &w, &h, &c, 0);
    ASSERT_NE(px, nullptr) << v;
    EXPECT_EQ(w, 160);
    EXPECT_EQ(h, 160);
    EXPECT_EQ(c, 1);
    long lit = 0;
    for (int i = 0; i < w * h; ++i) lit += px[i] > 40;
    EXPECT_GT(lit, w * h / 5) << v << " is mostly dark";
    stbi_image_free(px);
  }
}

TEST(CliUltrasound, RefusesNonsenseNamingTheField) {
  struct Case { const char* args; const char* field; };
  for (const Case& k : {Case{"--gain-db 100", "ultrasound.gain_db"}, Case{"--depth-mm 0", "ultrasound.depth_mm"},
                        Case{"--frequency-mhz 0.5", "ultrasound.frequency_mhz"}, Case{"--width-mm 5", "ultrasound.width_mm"},
                        Case{"--fov-deg 270", "ultrasound.fov_deg"}, Case{"--radius-mm 0", "ultrasound.convex_radius_mm"},
                        Case{"--views us_axial", "--views"}}) {
    const fs::path out = ps::test::cli_temp_dir("ultrasound_bad");
    fs::remove_all(out);
    const auto r = run_cli("ultrasound " + kScene + " --out " + out.string() + " " + k.args);
    EXPECT_EQ(r.code, 2) << k.args << ": " << r.out;
    EXPECT_NE(r.out.find(k.field), std::string::npos) << k.args << ": " << r.out;
    EXPECT_FALSE(fs::exists(out / "us_transverse.png")) << k.args;
  }
}

}  // namespace
