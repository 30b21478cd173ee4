// Live command for the instruments: a small POD that a user-interface, device or script fills and
// the physics thread applies at the start of the tick it is stamped with (engine/realtime/
// command_apply.h). Plain data, no pointers or strings, so it crosses threads by copy and is
// written to a recording as is. SI units.
//
// Addressing: `tool` is the index in Simulation::tools() (build_scene's order, fixed per
// scenario), `item` the instrument inside that tool (the needle index of the needle tool, -1 for
// tools with one instrument). A tool sees only the commands addressed to it (Tool::apply), so the
// realtime layer routes by number and never names a concrete tool.
#pragma once
#include <cstdint>

namespace ps {

enum class CommandKind : uint8_t {
  ProbeMove,     // probe: pose (insertion, offset, roll, tilt, yaw) reached over `duration`
  FillRate,      // filling: `component` at rate `value` [m^3/s]
  FillTo,        // filling: `component` to volume `value` [m^3] over `duration`
  NeedleAim,     // needle `item`: commanded tip `pos`, direction `dir`, then moving along `dir`
                 // at `speed` [m/s] (0: held) from this tick on; takes the needle off its script
  NeedleAdvance, // needle `item`: from where its command is now, along its commanded direction at
                 // `speed` [m/s] (negative: retract; 0: stop)
  NeedleRotate,  // needle `item`: hub rotation about the shaft to `angle` [rad] (kept and shown;
                 // the symmetric needle model has no bevel, so no mechanical effect)
  NeedleRelease, // needle `item`: back to its scenario script
  FireGun,       // needle `item`: fire the biopsy gun now
  DepositSeed,   // needle `item`: release the next seed at the tip now
  SelectNeedle,  // needle `item` becomes the active instrument (read-outs, devices)
  SelectHole,    // needle `item`: aim along template hole (`col`, `row`) of the probe, tip at the
                 // template, held
  NeedleDepth,   // needle `item`: tip at `depth` [m] along its path (a needle in the probe's
                 // guide: beyond the guide's exit at the probe's pose; the gun's stroke included),
                 // then moving along it at `speed` [m/s] (0: held)
};
inline constexpr int kCommandKinds = 12;
const char* command_kind_name(CommandKind k);
// -1 when unknown
int command_kind_from_name(const char* name);

// Each instrument kind reads its own payload (engine/tools/tool_kind.h); a command carries the one
// of its kind, the others keep their defaults. Separate members rather than a union, so a command
// stays trivially copyable, fully initialised and well defined to copy across threads and write
// to a recording.

// ProbeMove: the probe's target pose (ScenarioSpec ProbePose fields), reached over `duration`.
struct ProbeMovePayload {
  double insertion = 0.0;       // [m]
  double offset[3] = {0, 0, 0}; // [m]
  double roll = 0.0, tilt = 0.0, yaw = 0.0;  // [rad]
  double duration = 0.0;        // [s]
};

// FillRate / FillTo: an organ's filling.
struct FillPayload {
  int component = -1;           // Model component index of the organ
  double value = 0.0;           // FillRate [m^3/s]; FillTo [m^3]
  double duration = 0.0;        // FillTo [s]
};

// The needle commands (the needle is Command::item).
struct NeedlePayload {
  double pos[3] = {0, 0, 0};    // NeedleAim: tip [m]
  double dir[3] = {0, 0, 1};    // NeedleAim: direction (normalised by the tool)
  double speed = 0.0;           // NeedleAim / NeedleAdvance / NeedleDepth [m/s] (negative: retract)
  double angle = 0.0;           // NeedleRotate: hub rotation [rad]
  double depth = 0.0;           // NeedleDepth: tip depth along the path [m]
  int col = 0, row = 0;         // SelectHole: template hole
};

struct Command {
  CommandKind kind = CommandKind::ProbeMove;
  int64_t tick = 0;             // applied before this tick runs (ticks counted from 0)
  int16_t tool = -1;            // index in Simulation::tools(); -1: the first tool that takes it
  int16_t item = -1;            // instrument inside the tool (needle index), -1 if none
  ProbeMovePayload probe;       // ProbeMove
  FillPayload fill;             // FillRate, FillTo
  NeedlePayload needle;         // the needle kinds
};

}  // namespace ps
