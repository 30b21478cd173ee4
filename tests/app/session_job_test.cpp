// scripts/session_job.sh and the GNU parallel lines of docs/batch.md, run as written (only the
// scenario path changed): two short recordings of two trainees are replayed in parallel, each
// writes metrics.json and report.png, and `prostatesim report` merges them into sessions.csv.
// A list line that names a missing recording stops the batch with exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app/run_cli.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace {

namespace fs = std::filesystem;

using ps::test::read_text;  // tests/app/run_cli.h

// The first ```bash block after `heading` in docs/batch.md.
std::string doc_block(const std::string& heading) {
  const std::string d = read_text(fs::path(PROSTATESIM_SOURCE_DIR) / "docs" / "batch.md");
  const size_t h = d.find(heading);
  if (h == std::string::npos) return {};
  const size_t b = d.find("```bash\n", h);
  const size_t e = d.find("```", b + 8);
  return d.substr(b + 8, e - b - 8);
}

int shell(const std::string& cwd, const std::string& script) {
  const fs::path f = fs::path(cwd) / "batch.sh";
  std::ofstream(f) << "set -euo pipefail\nexport PATH=\"" << fs::path(PROSTATESIM_BINARY).parent_path().string() << ":$PATH\"\n"
                   << script;
  const int st = std::system(("cd " + cwd + " && bash batch.sh > batch.log 2>&1").c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(BatchScript, DocumentedParallelLinesReplayTwoRecordings) {
  if (std::system("command -v parallel > /dev/null 2>&1") != 0) GTEST_SKIP() << "GNU parallel not installed";
  const fs::path dir = ps::test::cli_temp_dir("session_job");
  fs::create_directory_symlink(fs::path(PROSTATESIM_SOURCE_DIR) / "scripts", dir / "scripts");
  fs::create_directories(dir / "config");
  const fs::path scen = dir / "config" / "block.yaml";
  std::ofstream(scen) << ps::test::block_yaml(ps::test::BlockOptions{},
                                              ps::test::vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]", "      target_mm: [0, 0, -12]\n"));
  // two trainees' recordings (different lengths: the shorter needle stops short of its target)
  for (auto [who, dur] : {std::pair<const char*, const char*>{"alice", "0.8"}, {"bob", "0.3"}}) {
    fs::create_directories(dir / "class" / who);
    const auto r = ps::test::run_cli("run " + scen.string() + " --headless --unpaced --duration " + dur + " --record " +
                                     (dir / "class" / who / "2026-12-01.rec").string());
    ASSERT_EQ(r.code, 0) << r.out;
  }
  std::string cmds = doc_block("## One machine: GNU parallel");
  ASSERT_NE(cmds.find("parallel -j"), std::string::npos) << cmds;
  const std::string from = "config/biopsy.yaml";
  ASSERT_NE(cmds.find(from), std::string::npos);
  cmds.replace(cmds.find(from), from.size(), "config/block.yaml");
  ASSERT_EQ(shell(dir.string(), cmds), 0) << read_text(dir / "batch.log");
  for (const char* who : {"alice", "bob"}) {
    const fs::path out = dir / "out" / "class" / who / "2026-12-01";
    EXPECT_TRUE(fs::exists(out / "metrics.json")) << out;
    EXPECT_TRUE(fs::exists(out / "report.png")) << out;
    EXPECT_NE(read_text(out / "metrics.json").find(std::string("\"trainee\": \"") + who + "\""), std::string::npos);
  }
  const std::string csv = read_text(dir / "out" / "class_report" / "sessions.csv");
  EXPECT_NE(csv.find("alice"), std::string::npos) << csv;
  EXPECT_NE(csv.find("bob"), std::string::npos) << csv;
  EXPECT_TRUE(fs::exists(dir / "out" / "class_report" / "summary.png"));
  // a line naming a missing recording: exit 2 from the job, the batch stops
  std::ofstream(dir / "bad.txt") << "config/block.yaml class/carol/none.rec\n";
  EXPECT_NE(shell(dir.string(), "scripts/session_job.sh bad.txt out/bad 1\n"), 0);
  EXPECT_NE(read_text(dir / "batch.log").find("none.rec"), std::string::npos) << read_text(dir / "batch.log");
}

}  // namespace
