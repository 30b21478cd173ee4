// `prostatesim insert` writes the same session report as `run --report` / `replay --report`
// (app/cmd_insert.cpp through app/session/session_capture.h): on a needles-only scene, insert and a
// replay of an empty script give the same metrics.json (score included), the same force-depth
// CSV and the same report.png, pixel for pixel (the 3D view of targets and needles included).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "engine/metrics/metrics_json.h"
#include "tests/app/run_cli.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace {

namespace fs = std::filesystem;
using ps::test::read_text;
using ps::test::run_cli;

TEST(InsertReport, InsertWritesTheSameSessionReportAsReplay) {
  const fs::path dir = ps::test::cli_temp_dir("insert_report");
  const fs::path scen = dir / "block.yaml", script = dir / "empty.yaml";
  std::ofstream(scen) << ps::test::block_yaml(ps::test::BlockOptions{},
                                              ps::test::vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]", "      target_mm: [3, 0, -12]\n"));
  std::ofstream(script) << "timeline: []\n";
  const fs::path a = dir / "insert" / "s1", b = dir / "replay" / "s1";
  const auto ri = run_cli("insert " + scen.string() + " --duration 0.6 --trainee bob --out " + a.string());
  ASSERT_EQ(ri.code, 0) << ri.out;
  const auto rr = run_cli("replay " + scen.string() + " --script " + script.string() + " --duration 0.6 --trainee bob --report " + b.string());
  ASSERT_EQ(rr.code, 0) << rr.out;
  for (const char* f : {"metrics.json", "report.png", "force_depth_n.csv", "needle_events.csv", "seeds.csv", "cores.csv"}) {
    ASSERT_TRUE(fs::exists(a / f)) << "insert did not write " << f;
    ASSERT_TRUE(fs::exists(b / f)) << "replay did not write " << f;
  }
  const std::string ma = read_text(a / "metrics.json"), mb = read_text(b / "metrics.json");
  EXPECT_EQ(ma, mb) << "insert and replay metrics.json differ";
  const ps::MetricsRow row = ps::parse_metrics_json(ma, (a / "metrics.json").string());
  std::printf("insert: score %.1f, mean error %.3f mm; replay: the same file (%zu bytes)\n", row.score, row.mean_error_mm, mb.size());
  EXPECT_NEAR(row.mean_error_mm, 3.0, 1.0);  // aimed at a target 3 mm to the side of its path
  EXPECT_GT(row.score, 0.0);
  EXPECT_EQ(read_text(a / "force_depth_n.csv"), read_text(b / "force_depth_n.csv"));
  // the report page: the same pixels (std::ifstream in binary: PNG bytes)
  auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string pa = bytes(a / "report.png"), pb = bytes(b / "report.png");
  EXPECT_GT(pa.size(), 20000u) << "a near-empty report page";
  EXPECT_TRUE(pa == pb) << "insert's report.png (" << pa.size() << " bytes) differs from replay's (" << pb.size() << " bytes)";
}

}  // namespace
