// Applies stamped live commands to the instruments on the physics thread, between ticks (the
// tools' commands insert schedule segments and may write a clamp report, so they run outside
// Simulation::step, which must not allocate; the queue itself never allocates).
//
// The loop calls apply_due(queue, tick) before running tick `tick`: it pops every command stamped
// <= tick, in the order pushed, and applies it. Commands must be pushed with non-decreasing
// stamps (a later stamp at the head proves every command for this tick has arrived); a command
// stamped for an earlier tick that arrives late is applied now and counted in late(). A command
// the tools refuse (e.g. a non-finite pose, a tilt beyond 45 degrees, an organ that is not
// filled) is not applied, and counted in refused() with the tool's message in reports(); it never
// stops the physics.
//
// Determinism: the state after N ticks depends only on (tick, command) pairs as applied, so a
// producer thread pushing while the physics ticks gives the same bits as one thread applying the
// same stamped commands (tests/engine/realtime/command_queue_test.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "engine/model/model.h"
#include "engine/realtime/command.h"
#include "engine/realtime/command_queue.h"

namespace ps {

class ProbeTool;
class FillingTool;

class CommandApplier {
 public:
  // Either tool may be null: a command for a missing tool is refused and reported.
  CommandApplier(const Model& model, ProbeTool* probe, FillingTool* filling) : m_(model), probe_(probe), filling_(filling) {}

  // Applies one command now (the physics thread, between ticks). False if refused.
  bool apply(const Command& c);
  // Pops and applies every queued command stamped <= tick. Returns how many were popped.
  // `complete` (optional) is set when the head of the queue is stamped after tick, i.e. every
  // command for this tick is known to have arrived.
  int apply_due(CommandQueue& q, int64_t tick, bool* complete = nullptr);

  int64_t applied() const { return applied_; }
  int64_t late() const { return late_; }
  int64_t refused() const { return refused_; }
  const std::vector<std::string>& reports() const { return reports_; }

 private:
  const Model& m_;
  ProbeTool* probe_;
  FillingTool* filling_;
  int64_t applied_ = 0, late_ = 0, refused_ = 0;
  std::vector<std::string> reports_;
};

}  // namespace ps
