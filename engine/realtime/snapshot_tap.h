// A second way to read the physics thread's snapshots, for readers beside the one that takes the
// triple buffer (the window): the OpenIGTLink server, and any other observer that wants a
// snapshot now and then. The physics thread offers each published snapshot (PhysicsLoop::publish);
// every `every_ticks`-th tick it copies it into the tap, unless a reader holds the tap's lock at
// that moment (try_lock: the physics never waits; the copy is then taken at the next tick).
// Readers (any number, any thread) copy the newest one out with take(). A copy reuses the
// vectors' capacity: after the first, offering allocates nothing.
#pragma once
#include <cstdint>
#include <mutex>

#include "engine/contract/snapshot.h"

namespace ps {

class SnapshotTap {
 public:
  explicit SnapshotTap(int every_ticks = 1) : every_(every_ticks < 1 ? 1 : every_ticks) {}

  // The physics thread, after filling `s` (ticks completed: s.tick).
  void offer(const Snapshot& s) {
    if (s.tick < next_ && s.tick >= last_) return;  // a reset or a load goes back: copy at once
    std::unique_lock<std::mutex> lk(mu_, std::try_to_lock);
    if (!lk.owns_lock()) return;
    snap_.tick = s.tick;
    snap_.time = s.time;
    snap_.x = s.x;
    snap_.draw = s.draw;
    snap_.tools = s.tools;
    snap_.state_hash = s.state_hash;
    snap_.faulted = s.faulted;
    snap_.fault = s.fault;
    ++version_;
    last_ = s.tick;
    next_ = s.tick + every_;
  }

  // Copies the newest snapshot into `out` when it is newer than `version` (then updated).
  // Events are not carried (readers of a tap follow poses and images). False when nothing new.
  bool take(Snapshot& out, uint64_t& version) {
    std::lock_guard<std::mutex> lk(mu_);
    if (version_ == version) return false;
    out.tick = snap_.tick;
    out.time = snap_.time;
    out.x = snap_.x;
    out.draw = snap_.draw;
    out.tools = snap_.tools;
    out.state_hash = snap_.state_hash;
    out.faulted = snap_.faulted;
    out.fault = snap_.fault;
    version = version_;
    return true;
  }
  int every_ticks() const { return every_; }

 private:
  const int every_;
  std::mutex mu_;
  Snapshot snap_;
  uint64_t version_ = 0;
  int64_t last_ = -1, next_ = 0;  // physics thread only
};

}  // namespace ps
