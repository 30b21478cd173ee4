// Tests of the window's worker threads (dose_worker.h, ultrasound_worker.h): submit a snapshot and
// wait (up to 30 s) for the worker's next frame of it.
#pragma once
#include <chrono>
#include <thread>

#include "engine/contract/snapshot.h"

namespace ps::gui::test {

template <class Frame, class Worker>
Frame next_frame(Worker& w, const Snapshot& snap) {
  Frame f;
  w.submit(snap);
  for (int k = 0; k < 3000 && !w.take(f); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return f;
}

}  // namespace ps::gui::test
