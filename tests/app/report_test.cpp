// `prostatesim report` as a user runs it (app/cmd_report.cpp): sessions from `insert` merged into
// sessions.csv and summary.png; a garbled or incomplete metrics.json exits 2 naming the file and
// the field, writing nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app/run_cli.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace {

namespace fs = std::filesystem;
using ps::test::run_cli;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void insert_session(const fs::path& dir, const std::string& trainee, const std::string& session, const std::string& target_mm) {
  const fs::path scen = dir / (trainee + session + ".yaml");
  std::ofstream(scen) << ps::test::block_yaml(ps::test::BlockOptions{},
                                              ps::test::vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]", "      target_mm: " + target_mm + "\n"));
  const auto r = run_cli("insert " + scen.string() + " --duration 0.7 --trainee " + trainee + " --session " + session + " --out " +
                         (dir / "class" / trainee / session).string());
  ASSERT_EQ(r.code, 0) << r.out;
}

TEST(Report, MergesSessionsIntoCsvAndSummaryPicture) {
  const fs::path dir = ps::test::cli_temp_dir("report_ok");
  insert_session(dir, "alice", "s1", "[6, 0, -12]");
  insert_session(dir, "alice", "s2", "[2, 0, -12]");
  insert_session(dir, "bob", "s1", "[0, 0, -12]");
  const fs::path out = dir / "report";
  const auto r = run_cli("report " + (dir / "class").string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("3 sessions, 2 trainees"), std::string::npos) << r.out;
  const std::string csv = read(out / "sessions.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4) << csv;
  EXPECT_NE(csv.find("alice,s1,1,needle_block,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("alice,s2,2,needle_block,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("bob,s1,1,needle_block,"), std::string::npos) << csv;
  const std::string png = read(out / "summary.png");
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // IHDR: width and height, big-endian, at bytes 16..23
  auto be32 = [&](size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(be32(16), 1600u);
  EXPECT_EQ(be32(20), 1120u);
}

TEST(Report, BadMetricsExit2NamingFileAndFieldAndWriteNothing) {
  const fs::path dir = ps::test::cli_temp_dir("report_bad");
  insert_session(dir, "alice", "s1", "[0, 0, -12]");
  std::string good = read(dir / "class" / "alice" / "s1" / "metrics.json");
  struct Case {
    std::string name, content, words;
  };
  std::string no_trainee = good;
  no_trainee.replace(no_trainee.find("\"trainee\""), 9, "\"trainer\"");
  std::string bad_score = good;
  const size_t at = bad_score.find("\"score\": ") + 9;
  bad_score.replace(at, bad_score.find(',', at) - at, "\"high\"");
  const std::vector<Case> cases = {{"garbled", "{\"format\": ", "not valid JSON"},
                                   {"no_trainee", no_trainee, "'trainee': missing"},
                                   {"bad_score", bad_score, "'score': expected a number"}};
  for (const Case& c : cases) {
    const fs::path s = dir / c.name;
    fs::create_directories(s);
    std::ofstream(s / "metrics.json") << c.content;
    const fs::path out = dir / ("out_" + c.name);
    const auto r = run_cli("report " + (dir / "class").string() + " " + s.string() + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find((s / "metrics.json").string()), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(c.words), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
  const auto none = run_cli("report " + (dir / "nowhere").string() + " --out " + (dir / "out_none").string());
  EXPECT_EQ(none.code, 2) << none.out;
  EXPECT_NE(none.out.find("nowhere"), std::string::npos) << none.out;
}

}  // namespace
