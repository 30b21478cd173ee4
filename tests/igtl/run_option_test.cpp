// `prostatesim run ... --igtl-port 0` headless: the server says its port, serves while the
// physics runs and stops with it.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace {

std::string run(const std::string& args, int* rc) {
  std::string out;
  FILE* p = popen((std::string(PROSTATESIM_BINARY) + " " + args + " 2>&1").c_str(), "r");
  char buf[512];
  while (p && std::fgets(buf, sizeof buf, p)) out += buf;
  const int st = p ? pclose(p) : -1;
  *rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return out;
}

TEST(IgtlRunOption, HeadlessRunServesAndStops) {
  int rc = -1;
  const std::string out = run("run " PROSTATESIM_SOURCE_DIR "/config/biopsy.yaml --headless --unpaced --duration 0.1 --igtl-port 0", &rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("OpenIGTLink: serving on port "), std::string::npos) << out;
  EXPECT_NE(out.find("transforms and"), std::string::npos) << out;
}

TEST(IgtlRunOption, APortOutOfRangeIsBadInput) {
  int rc = -1;
  const std::string out = run("run " PROSTATESIM_SOURCE_DIR "/config/biopsy.yaml --headless --duration 0.1 --igtl-port 70000", &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("--igtl-port"), std::string::npos) << out;
}

}  // namespace
