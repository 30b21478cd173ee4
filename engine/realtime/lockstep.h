// Headless lock-step driver: no thread, no wall clock. Advance to tick N, read the snapshot,
// repeat (headless replay, `replay --hash`, the PNG frame writer, tests). Gives the same bits as
// the real-time PhysicsLoop for the same sources: both run engine/realtime/tick_runner.h.
//
//   LockstepRunner run(*scene.sim);
//   run.add_source(&script);               // or a RecordingPlayer
//   while (run.tick() < end) {
//     run.advance_to(run.tick() + ticks_per_frame);
//     const Snapshot& s = run.snapshot();  // filled on demand, events since the last call
//   }
#pragma once
#include "engine/realtime/tick_runner.h"

namespace ps {

class LockstepRunner {
 public:
  explicit LockstepRunner(Simulation& sim, size_t queue_capacity = 1024) : runner_(sim, queue_capacity) {}

  void add_source(CommandSource* s) { runner_.add_source(s); }
  CommandApplier& applier() { return runner_.applier(); }
  CommandQueue& queue() { return runner_.queue(); }
  Simulation& sim() { return runner_.sim(); }
  TickRunner& runner() { return runner_; }

  // Runs ticks until tick() == n (or a fault). False when the simulation faulted.
  bool advance_to(int64_t n) {
    while (runner_.tick() < n)
      if (!runner_.step()) return false;
    return true;
  }
  bool step() { return runner_.step(); }
  int64_t tick() const { return runner_.tick(); }
  double time() const { return runner_.sim().state().time; }
  bool faulted() const { return runner_.faulted(); }
  void reset() { runner_.reset(); }
  // Snapshot of the current tick; events since the previous call. with_hash: state_hash filled.
  const Snapshot& snapshot(bool with_hash = false) {
    runner_.fill_snapshot(snap_, false, with_hash);
    return snap_;
  }
  uint64_t hash() { return runner_.sim().hash(); }

 private:
  TickRunner runner_;
  Snapshot snap_;
};

}  // namespace ps
