// A second way to read the live simulation, for readers beside the one that takes the physics
// loop's snapshots (the window): the OpenIGTLink server, and any other observer that wants a
// snapshot now and then. A CommandSource that applies nothing: after every `every_ticks`-th tick
// (on the physics thread, between ticks, outside the step) it copies the positions, the
// instruments' geometry and read-outs into the tap, unless a reader holds the tap's lock at that
// moment (try_lock: the physics never waits; the copy is then taken after the next tick).
// Readers (any number, any thread) copy the newest one out with take(). Events are not carried
// (the loop's own snapshots have them). The buffers keep their capacity: after the first copy,
// nothing is allocated.
#pragma once
#include <cstdint>
#include <cstdio>
#include <mutex>

#include "engine/contract/snapshot.h"
#include "engine/realtime/tick_runner.h"

namespace ps {

class SnapshotTap final : public CommandSource {
 public:
  explicit SnapshotTap(int every_ticks = 1) : every_(every_ticks < 1 ? 1 : every_ticks) {}

  void poll(int64_t, const Simulation&, CommandApplier&) override {}
  void after_tick(int64_t tick, const Simulation& sim) override {
    if (tick < next_ && tick >= last_) return;  // a reset or a load goes back: copy at once
    std::unique_lock<std::mutex> lk(mu_, std::try_to_lock);
    if (!lk.owns_lock()) return;
    const Model& m = sim.model();
    const State& s = sim.state();
    snap_.tick = tick;
    snap_.time = s.time;
    snap_.x.resize(3 * s.x.size());
    for (size_t i = 0; i < s.x.size(); ++i)
      for (int k = 0; k < 3; ++k) snap_.x[3 * i + static_cast<size_t>(k)] = static_cast<float>(s.x[i][k]);
    snap_.draw.clear();
    const auto& tools = sim.tools();
    snap_.tools.resize(tools.size());
    for (size_t i = 0; i < tools.size(); ++i) {
      tools[i]->draw(snap_.draw, m, s);
      ToolReadout& r = snap_.tools[i];
      r = ToolReadout{};
      std::snprintf(r.name.data(), r.name.size(), "%s", tools[i]->name());
      tools[i]->readout(r, m, s);
    }
    snap_.faulted = s.fault.kind != StepFault::None;
    ++version_;
    last_ = tick;
    next_ = tick + every_;
  }
  void rewind() override { last_ = -1, next_ = 0; }
  void seek(int64_t) override { rewind(); }

  // Copies the newest snapshot into `out` when it is newer than `version` (then updated).
  // False when nothing new.
  bool take(Snapshot& out, uint64_t& version) {
    std::lock_guard<std::mutex> lk(mu_);
    if (version_ == version) return false;
    out.tick = snap_.tick;
    out.time = snap_.time;
    out.x = snap_.x;
    out.draw = snap_.draw;
    out.tools = snap_.tools;
    out.events.clear();
    out.faulted = snap_.faulted;
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
