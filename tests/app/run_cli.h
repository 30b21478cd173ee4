// Runs the prostatesim binary built with the tests and captures its exit code and output.
#pragma once
#include <sys/wait.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

namespace ps::test {

struct CliResult {
  int code;          // exit status, -1 if killed by a signal
  std::string out;   // stdout and stderr together
};

inline CliResult run_cli(const std::string& args) {
  const std::string cmd = std::string(PROSTATESIM_BINARY) + " " + args + " 2>&1";
  CliResult r{0, ""};
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Folders made by cli_temp_dir in this test process.
inline std::vector<std::filesystem::path>& cli_temp_dirs() {
  static std::vector<std::filesystem::path> dirs;
  return dirs;
}

// Removes those folders when the whole test program passed (a failure keeps them to look at).
class CliTempDirCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    if (!::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ec;
    for (const auto& d : cli_temp_dirs()) std::filesystem::remove_all(d, ec);
  }
};
inline const bool kCliTempDirCleanupRegistered =
    (::testing::AddGlobalTestEnvironment(new CliTempDirCleanup), true);

// A fresh empty folder for one test: <tmp>/prostatesim_<name>_<pid>, removed after a passing run.
inline std::filesystem::path cli_temp_dir(const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("prostatesim_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  cli_temp_dirs().push_back(d);
  return d;
}

// A whole file as text ("" if it cannot be read).
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace ps::test
