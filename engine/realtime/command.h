// Live command for the instruments (issue 5; the realtime issue builds on it): a small POD that a
// user-interface or haptic thread fills and pushes through a CommandQueue, and the physics
// thread applies at the start of the tick it is stamped with (engine/realtime/command_apply.h).
// Plain data, no pointers or strings, so it crosses threads by copy. SI units.
#pragma once
#include <cstdint>

namespace ps {

enum class CommandKind : uint8_t {
  ProbeMove,   // ProbeTool::move_to(pose, duration)
  FillRate,    // FillingTool::set_rate(component, rate)
  FillTo,      // FillingTool::fill_to(component, target, duration)
};

struct Command {
  CommandKind kind = CommandKind::ProbeMove;
  int64_t tick = 0;             // applied before this tick runs (ticks counted from 0)
  int component = -1;           // FillRate / FillTo: Model component index of the organ
  // ProbeMove: target pose (ScenarioSpec ProbePose fields)
  double insertion = 0.0;       // [m]
  double offset[3] = {0, 0, 0}; // [m]
  double roll = 0.0, tilt = 0.0, yaw = 0.0;  // [rad]
  double duration = 0.0;        // ProbeMove, FillTo [s]
  double value = 0.0;           // FillRate: rate [m^3/s]; FillTo: target volume [m^3]
};

}  // namespace ps
