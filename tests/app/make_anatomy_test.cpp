// `prostatesim make-anatomy` reproduces the committed assets byte for byte, and `check` compiles
// the default scenario within its time budget.
#include <gtest/gtest.h>

#include "tests/app/run_cli.h"
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

using Result = ps::test::CliResult;
using ps::test::run_cli;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(MakeAnatomy, ReproducesTheCommittedAssets) {
  const fs::path out = fs::temp_directory_path() / ("prostatesim_anatomy_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const Result r = run_cli("make-anatomy --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("prostate"), std::string::npos);
  EXPECT_NE(r.out.find("29.43"), std::string::npos) << r.out;   // prostate volume [cm^3]
  const fs::path assets = fs::path(PROSTATESIM_SOURCE_DIR) / "assets" / "anatomy";
  int files = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    ++files;
    EXPECT_TRUE(slurp(e.path()) == slurp(assets / e.path().filename())) << e.path().filename() << " differs from the committed asset";
  }
  EXPECT_EQ(files, 7);
  fs::remove_all(out);
}

TEST(MakeAnatomy, CheckCompilesTheDefaultScenario) {
  const Result r = run_cli("check " + (fs::path(PROSTATESIM_SOURCE_DIR) / "config" / "biopsy.yaml").string());
  ASSERT_EQ(r.code, 0) << r.out;
  double seconds = -1;
  const size_t at = r.out.find("compiled in ");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::sscanf(r.out.c_str() + at, "compiled in %lf", &seconds);
  EXPECT_GT(seconds, 0.0);
  EXPECT_LE(seconds, 2.0) << r.out;
  EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
}

}  // namespace
