#pragma once
// This thread's CPU time [ns] (CLOCK_THREAD_CPUTIME_ID): what a tick cost the thread that ran it,
// without the time the host gave the core to someone else. For the benchmarks and `prostatesim
// bench`; the physics step reads no clock.
#include <cstdint>
#include <ctime>

namespace ps {

inline int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

}  // namespace ps
