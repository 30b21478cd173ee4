// metrics.json written by `prostatesim insert` (engine/metrics, docs/metrics.md): a needle
// scripted onto its target scores about 0 mm, one aimed 5 mm off about 5 mm; the file reads back
// through the same parser `report` uses; a target outside every organ is bad input (exit 2,
// nothing written).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/metrics/metrics_json.h"
#include "tests/app/run_cli.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace {

namespace fs = std::filesystem;
using ps::test::BlockOptions;
using ps::test::block_yaml;
using ps::test::run_cli;
using ps::test::vertical_needle;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Result {
  ps::MetricsRow row;
  std::string text;
};

Result run_aimed(const std::string& name, const std::string& target_mm, int expect_code = 0) {
  const fs::path dir = ps::test::cli_temp_dir("insert_metrics_" + name);
  const fs::path scen = dir / "block.yaml";
  std::ofstream(scen) << block_yaml(BlockOptions{}, vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]", "      target_mm: " + target_mm + "\n"));
  const fs::path out = dir / "out";
  const auto r = run_cli("insert " + scen.string() + " --duration 0.8 --trainee alice --out " + out.string());
  EXPECT_EQ(r.code, expect_code) << r.out;
  if (expect_code != 0) {
    EXPECT_FALSE(fs::exists(out)) << "nothing written on bad input";
    EXPECT_NE(r.out.find("block.yaml:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("needles.instruments[0].target_mm"), std::string::npos) << r.out;
    return {};
  }
  EXPECT_NE(r.out.find("score "), std::string::npos) << r.out;
  const std::string text = read(out / "metrics.json");
  const ps::MetricsRow row = ps::parse_metrics_json(text, (out / "metrics.json").string());
  EXPECT_EQ(row.trainee, "alice");
  EXPECT_EQ(row.session, "out");
  return {row, text};
}

TEST(InsertMetrics, OnTargetAboutZeroAndFiveMillimetresOffAboutFive) {
  const Result on = run_aimed("on", "[0, 0, -12]");
  const Result off = run_aimed("off", "[5, 0, -12]");
  std::printf("metrics.json: on target %.3f mm (score %.1f), 5 mm off %.3f mm (score %.1f)\n", on.row.mean_error_mm, on.row.score,
              off.row.mean_error_mm, off.row.score);
  EXPECT_LT(on.row.mean_error_mm, 1.0);
  EXPECT_NEAR(off.row.mean_error_mm, 5.0, 1.0);
  EXPECT_GT(on.row.score, off.row.score);
  EXPECT_EQ(on.row.needles, 1);
  EXPECT_EQ(on.row.punctures, 1);
  EXPECT_NE(on.text.find("\"freehand_mm\": 9.0"), std::string::npos) << on.text;
  EXPECT_NE(on.text.find("\"robot_mm\": 1.0"), std::string::npos) << on.text;
}

TEST(InsertMetrics, TargetOutsideEveryOrganIsBadInput) { run_aimed("outside", "[0, 0, 40]", 2); }

}  // namespace
