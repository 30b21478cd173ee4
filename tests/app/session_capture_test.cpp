// The session report of `run` and `replay` (app/session/session_capture.h): a needle scripted onto its
// target scores about 0 mm at the end of a headless run, the replay of its recording writes the
// same metrics, both write report.png; --report on a scenario without needles, or an output path
// that is a file, is bad input (exit 2, nothing written).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/metrics/metrics_json.h"
#include "tests/app/run_cli.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace {

namespace fs = std::filesystem;

using ps::test::read_text;  // tests/app/run_cli.h

ps::MetricsRow metrics_in(const fs::path& dir) { return ps::parse_metrics_json(read_text(dir / "metrics.json"), (dir / "metrics.json").string()); }

TEST(SessionCapture, RunAndReplayWriteTheSameMetricsAndTheReport) {
  const fs::path dir = ps::test::cli_temp_dir("session_capture");
  const fs::path scen = dir / "block.yaml";
  std::ofstream(scen) << ps::test::block_yaml(ps::test::BlockOptions{},
                                              ps::test::vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]", "      target_mm: [0, 0, -12]\n"));
  const fs::path rec = dir / "s.rec", out_run = dir / "run", out_rep = dir / "replay";
  const auto r = ps::test::run_cli("run " + scen.string() + " --headless --unpaced --duration 0.8 --record " + rec.string() + " --report " +
                                   out_run.string() + " --trainee bob --session 2026-12-01");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("score "), std::string::npos) << r.out;
  const ps::MetricsRow a = metrics_in(out_run);
  EXPECT_EQ(a.trainee, "bob");
  EXPECT_EQ(a.session, "2026-12-01");
  EXPECT_LT(a.mean_error_mm, 1.0) << "scripted onto its target";
  EXPECT_EQ(a.punctures, 1);
  EXPECT_GT(fs::file_size(out_run / "report.png"), 10000u);
  EXPECT_TRUE(fs::exists(out_run / "force_depth_n.csv"));
  const auto p = ps::test::run_cli("replay " + scen.string() + " --recording " + rec.string() + " --report " + out_rep.string() +
                                   " --trainee bob --session 2026-12-01");
  ASSERT_EQ(p.code, 0) << p.out;
  const ps::MetricsRow b = metrics_in(out_rep);
  EXPECT_EQ(b.mean_error_mm, a.mean_error_mm) << "replay is bit for bit";
  EXPECT_EQ(b.score, a.score);
  EXPECT_EQ(read_text(out_rep / "force_depth_n.csv"), read_text(out_run / "force_depth_n.csv"));
}

TEST(SessionCapture, BadReportOptionsExit2WritingNothing) {
  const fs::path dir = ps::test::cli_temp_dir("session_capture_bad");
  const fs::path scen = dir / "block.yaml";
  std::ofstream(scen) << ps::test::block_yaml(ps::test::BlockOptions{}, ps::test::vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]"));
  const fs::path file = dir / "a_file";
  std::ofstream(file) << "x";
  auto r = ps::test::run_cli("run " + scen.string() + " --headless --unpaced --duration 0.05 --report " + file.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--report"), std::string::npos) << r.out;
  // no needles: nothing to score
  const fs::path plain = dir / "plain.yaml";
  std::string y = read_text(scen);
  y = y.substr(0, y.find("needles:"));
  std::ofstream(plain) << y;
  r = ps::test::run_cli("run " + plain.string() + " --headless --unpaced --duration 0.05 --report " + (dir / "out").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("no needles"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "out")) << "nothing written on bad input";
}

}  // namespace
