#pragma once
// The xvfb-run prefix for the window tests, with two things xvfb-run does not do for tests run in
// parallel (ctest -j) on a loaded machine:
// - `xvfb-run -a` starts its search for a free X display at :99 in every process, so two window
//   tests started together can both take :99; each test process here starts at a display number
//   of its own (from its pid);
// - xvfb-run makes a temporary directory for the X authority file and removes it on exit; that
//   removal failed now and then under load, and xvfb-run then exits 5 instead of the program's
//   code (seen: EditorWindow.RefusedEditExits2AndLeavesTheFile under ctest -j2, "problem while
//   cleaning up temporary directory"). The test names its own authority file (in its own
//   temporary directory, which it removes), so xvfb-run makes none.
#include <unistd.h>

#include <string>

namespace ps::test {

inline std::string xvfb_run(const std::string& auth_file) {
  return "xvfb-run -a -n " + std::to_string(100 + static_cast<int>(::getpid() % 3000)) + " -f " + auth_file +
         " -s '-screen 0 1600x900x24' ";
}

}  // namespace ps::test
