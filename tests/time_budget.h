// Time bounds in tests (a compile within 2 s of CPU, a fuzz run within 20 s) are set for the
// Release build, where they catch a hang or a large slowdown. A sanitizer build runs the same
// code 5-15x slower (measured: the biopsy compile 12.6x, the mesh fuzz 6.2x under ASan+UBSan), so
// .ci/sanitize sets PROSTATESIM_TEST_TIME_SCALE and every bound is multiplied by it there; the
// bound itself, and the check, are the Release ones everywhere else.
#pragma once
#include <cstdlib>

namespace ps::test {

inline double time_budget(double seconds) {
  const char* s = std::getenv("PROSTATESIM_TEST_TIME_SCALE");
  const double k = s ? std::atof(s) : 1.0;
  return seconds * (k > 1.0 ? k : 1.0);
}

}  // namespace ps::test
