// Runs the prostatesim binary built with the tests and captures its exit code and output.
#pragma once
#include <sys/wait.h>

#include <cstdio>
#include <string>

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

}  // namespace ps::test
