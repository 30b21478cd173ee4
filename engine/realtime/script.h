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
#include "engine/util/vec.h"

namespace ps {

struct ScriptEntry {
  double t = 0.0;                  // [s]
  int line = 0;                    // in the script file
  std::string action;              // probe | needle | advance | fire | deposit_seed | select | hole |
                                   // rotate | release | fill_rate | fill_to
  std::string target;              // needle name / organ name ("" for the probe)
  // probe (fields not given keep the previous commanded value)
  bool has_insertion = false, has_offset = false, has_roll = false, has_tilt = false, has_yaw = false;
  double insertion = 0.0;          // [m]
  Vec3 offset = Vec3::Zero();      // [m]
  double roll = 0.0, tilt = 0.0, yaw = 0.0;  // [rad]
  double over = 0.0;               // probe move / fill_to duration [s]
  // needle
  double depth = 0.0;              // needle key: depth along its path [m]
  double speed = 0.0;              // advance [m/s]
  double angle = 0.0;              // rotate [rad]
  int col = 0, row = 0;            // hole
  double value = 0.0;              // fill_rate [m^3/s], fill_to [m^3]
};

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
