// Applies stamped live commands to the instruments on the physics thread, between ticks (the
// tools' commands may insert schedule segments, so they run outside Simulation::step, which must
// not allocate; the queue itself never allocates).
//
// Routing: a command goes to Simulation::tools()[c.tool] through Tool::apply, or, with
// c.tool = -1, to the first tool that accepts() its kind. This file names no concrete tool.
//
// The loop calls apply_due(queue, tick) before running tick `tick`: it pops every command stamped
// <= tick, in the order pushed, and applies it. Commands must be pushed with non-decreasing
// stamps (a later stamp at the head proves every command for this tick has arrived); a command
// stamped for an earlier tick that arrives late is applied now and counted in late(). A command
// the tools refuse (e.g. a non-finite pose, a tilt beyond 45 degrees, an organ that is not
// filled) is not applied, and counted in refused() with the tool's reason in a fixed ring of
// refusal reports (no allocation); it never stops the physics.
//
// Every applied command is also handed to an optional observer (the recorder), stamped with
// the tick it was actually applied at, so a replay applying the same (tick, command) pairs gives
// the same bits.
//
// Determinism: the state after N ticks depends only on (tick, command) pairs as applied, so a
// producer thread pushing while the physics ticks gives the same bits as one thread applying the
// same stamped commands (tests/engine/realtime/command_queue_test.cpp).
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "engine/contract/command.h"
#include "engine/realtime/command_queue.h"
#include "engine/step/simulation.h"

namespace ps {

struct RefusalReport {
  int64_t tick = 0;
  int tool = -1;
  CommandKind kind = CommandKind::ProbeMove;
  char text[120] = {0};
  std::string describe() const;  // "tick 12: needle_aim refused: ..." (outside the physics thread)
};

// Fixed ring of the latest refusals (oldest overwritten, counted).
class RefusalRing {
 public:
  static constexpr int kCapacity = 64;
  void push(const RefusalReport& r) {
    buf_[static_cast<size_t>(total_ % kCapacity)] = r;
    ++total_;
  }
  int64_t total() const { return total_; }
  int size() const { return static_cast<int>(total_ < kCapacity ? total_ : kCapacity); }
  // i-th oldest report still held
  const RefusalReport& at(int i) const { return buf_[static_cast<size_t>((total_ - size() + i) % kCapacity)]; }

 private:
  std::array<RefusalReport, kCapacity> buf_{};
  int64_t total_ = 0;
};

// Called for every command applied (tick = the tick it was applied at).
class CommandObserver {
 public:
  virtual ~CommandObserver() = default;
  virtual void applied(const Command& c) = 0;
};

class CommandApplier {
 public:
  explicit CommandApplier(Simulation& sim) : sim_(sim) {}

  // Applies one command now, before tick `tick` (the physics thread, between ticks). False if
  // refused (reported in refusals()).
  bool apply(const Command& c, int64_t tick);
  bool apply(const Command& c) { return apply(c, c.tick); }
  // Pops and applies every queued command stamped <= tick. Returns how many were popped.
  // `complete` (optional) is set when the head of the queue is stamped after tick, i.e. every
  // command for this tick is known to have arrived.
  int apply_due(CommandQueue& q, int64_t tick, bool* complete = nullptr);

  void set_observer(CommandObserver* o) { observer_ = o; }
  // A second observer, for the runner's own use (TickRunner's recovery log); called first.
  void set_log(CommandObserver* o) { log_ = o; }
  int64_t applied() const { return applied_; }
  int64_t late() const { return late_; }
  int64_t refused() const { return refused_; }
  const RefusalRing& refusals() const { return refusals_; }

 private:
  Simulation& sim_;
  CommandObserver* observer_ = nullptr;
  CommandObserver* log_ = nullptr;
  int64_t applied_ = 0, late_ = 0, refused_ = 0;
  RefusalRing refusals_;
};

}  // namespace ps
