// Scripted device: a YAML timeline of instrument poses and actions (config/scripts/*.yaml, format
// in docs/realtime.md), turned into stamped commands and applied at their ticks by a
// ScriptPlayer (a CommandSource). Used by `prostatesim run --script`, headless replay, the
// simulated haptic hand and tests.
//
// Interpolation: consecutive `depth_mm` keys of a needle are joined linearly: at each key the
// needle is aimed at start + depth * direction and set moving at the speed that reaches the next
// key on time (held at the last key). Probe poses are reached over `over_s` along the probe's
// own smoothstep. Times are rounded to the nearest tick.
//
// Bad input (not YAML, unknown action or key, an instrument the scene lacks, time going
// backwards): InputError naming file:line and the field; the CLI exits 2.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "engine/contract/command.h"
#include "engine/realtime/tick_runner.h"
#include "engine/sim/scene.h"
#include "engine/spec/timeline_entry.h"
#include "engine/util/vec.h"

namespace ps {

struct Script {
  std::string file;
  std::string scenario;            // name of the scenario it was written for ("" = any)
  double duration = 0.0;           // [s], 0: the last entry's time
  std::vector<ScriptEntry> entries;   // non-decreasing t
};

Script parse_script_text(const std::string& text, const std::string& file);
Script parse_script_file(const std::string& path);

// Commands of a script for a scene, sorted by tick (stable: file order within a tick). Throws
// InputError (file:line) for an instrument the scene lacks or a script for another scenario.
std::vector<Command> script_commands(const Script& script, const Scene& scene);

// Needle depth the script commands at time t [m] (linear between keys; the simulated haptic hand
// follows it). NaN when the script has no key for that needle.
double script_needle_depth(const Script& script, const std::string& needle, double t);

// Applies a command list at its ticks (scripts, recordings).
class CommandPlayer final : public CommandSource {
 public:
  explicit CommandPlayer(std::vector<Command> cmds) : cmds_(std::move(cmds)) {}
  void poll(int64_t tick, const Simulation&, CommandApplier& apply) override {
    while (next_ < cmds_.size() && cmds_[next_].tick <= tick) apply.apply(cmds_[next_++], tick);
  }
  void rewind() override { next_ = 0; }
  void seek(int64_t tick) override {
    next_ = 0;
    while (next_ < cmds_.size() && cmds_[next_].tick < tick) ++next_;
  }
  const std::vector<Command>& commands() const { return cmds_; }
  int64_t last_tick() const { return cmds_.empty() ? 0 : cmds_.back().tick; }

 private:
  std::vector<Command> cmds_;
  size_t next_ = 0;
};

}  // namespace ps
