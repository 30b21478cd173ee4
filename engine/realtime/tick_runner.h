// The one place a tick happens for live use, shared by the real-time PhysicsLoop (its own thread,
// wall-clock paced) and the LockstepRunner (no thread, no clock: headless replay, PNG frames,
// tests), so both give the same bits for the same (tick, command) pairs:
//   1. every CommandSource is polled (devices, scripts, a recording), in the order added;
//   2. the queue's commands stamped <= tick are applied (the UI thread's pushes);
//   3. Simulation::tick().
// Applied commands go to the observer (the recorder) stamped with the tick they were applied at.
// Snapshots: fill_snapshot() copies what readers need (engine/realtime/snapshot.h).
#pragma once
#include <cstdint>
#include <vector>

#include "engine/realtime/command_apply.h"
#include "engine/realtime/command_queue.h"
#include "engine/realtime/snapshot.h"
#include "engine/step/simulation.h"

namespace ps {

// Something polled once per tick on the physics thread that may apply commands (a device, a
// script, a recording). poll() runs between ticks; it must not block.
class CommandSource {
 public:
  virtual ~CommandSource() = default;
  // Applies this source's commands due before tick `tick` through `apply.apply(c, tick)`.
  virtual void poll(int64_t tick, const Simulation& sim, CommandApplier& apply) = 0;
  // Called after each tick with the simulation (force feedback to a device). Default: nothing.
  virtual void after_tick(int64_t /*tick*/, const Simulation& /*sim*/) {}
  // Back to the start (the loop's reset).
  virtual void rewind() {}
};

class TickRunner {
 public:
  // `sim` must outlive the runner. The initial state is saved for reset().
  explicit TickRunner(Simulation& sim, size_t queue_capacity = 1024);

  void add_source(CommandSource* s) { sources_.push_back(s); }
  CommandQueue& queue() { return queue_; }
  CommandApplier& applier() { return applier_; }
  Simulation& sim() { return sim_; }
  const Simulation& sim() const { return sim_; }

  // Runs one tick (polls, applies, ticks). False when the simulation faulted (it stays stopped).
  bool step(StageProbe* probe = nullptr);
  int64_t tick() const { return tick_; }        // ticks completed
  bool faulted() const { return faulted_; }
  // Back to the state at construction, tick 0, sources rewound, queue emptied.
  void reset();

  // Fills `out` with the current state. keep_events: `out` holds events not yet read (a
  // snapshot the reader skipped), so append to them instead of replacing them.
  void fill_snapshot(Snapshot& out, bool keep_events = false, bool with_hash = false);

 private:
  Simulation& sim_;
  CommandQueue queue_;
  CommandApplier applier_;
  std::vector<CommandSource*> sources_;
  int64_t tick_ = 0;
  bool faulted_ = false;
  std::vector<uint8_t> initial_;
  std::vector<int64_t> event_cursor_;  // per tool
  int64_t refusal_cursor_ = 0;
};

}  // namespace ps
