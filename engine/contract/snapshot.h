// What the physics thread publishes after a tick for readers (renderer, UI, ultrasound, metrics):
// a self-contained copy, so a reader never touches State while physics runs. Published through a
// lock-free triple buffer (engine/realtime/, the realtime issue); buffers are sized once and
// reused, so publishing does not allocate once warm.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "engine/draw/draw_sink.h"

namespace ps {

// What an instrument's read-out measures, as bits of ToolReadout::carries. The frontends that
// plot, print and frame any instrument (the force-versus-depth plot, the HUD, the cameras, the
// frames' traces) ask these, never which kind made the read-out.
enum ReadoutCarries : uint8_t {
  kCarriesInsertion = 1,  // depth and axial force along `axis` (a needle): force-versus-depth
  kCarriesImaging = 2,    // tip and axis are an imaging probe's pose; force its contact force
  kCarriesVolume = 4,     // value is a filled volume [m^3]
};
inline constexpr uint8_t kNoToolKind = 255;

// One instrument's read-out for panels and plots (force-versus-depth of the active needle).
struct ToolReadout {
  uint8_t kind = kNoToolKind;      // its kind's index in tool_kinds() (engine/tools/tool_kind.h):
                                   // a kind's own panel finds its read-outs by it
  uint8_t carries = 0;             // ReadoutCarries bits
  std::array<char, 32> name{};     // tool name, NUL-terminated
  Vec3 tip = Vec3::Zero();         // needle tip / probe tip [m]
  Vec3 axis = Vec3::UnitZ();       // unit insertion direction
  double depth = 0.0;              // needle: depth since first tissue contact [m]
  double force = 0.0;              // axial tissue force on the instrument [N] (needle: resisting
                                   // insertion is positive; probe: contact force magnitude)
  Vec3 force_vec = Vec3::Zero();   // total tissue force on the instrument [N]
  double value = 0.0;              // kCarriesVolume: the target volume [m^3]; else the kind's own
                                   // (probe: insertion [m], needle: planned depth [m])
  bool active = false;             // the instrument the user drives now
};

// SnapshotEvent::kind of a command the tools refused (tool-specific kinds are below 254).
inline constexpr uint8_t kSnapshotEventRefused = 255;
// SnapshotEvent::kind of a command a tool took but adjusted to its limits (a fill rate clamped, a
// probe move lengthened to the speed limits); the text says what was asked and what was used.
inline constexpr uint8_t kSnapshotEventAdjusted = 254;

// An event since the previous snapshot (puncture, bone hit, core, seed, fault, refused command).
struct SnapshotEvent {
  double time = 0.0;               // simulation time [s]
  int tool = -1;                   // index into Snapshot::tools, -1 if none
  uint8_t kind = 0;                // tool-specific kind (NeedleEventKind for needles)
  Vec3 position = Vec3::Zero();    // [m]
  double depth = 0.0;              // [m]
  double force = 0.0;              // [N]
  std::array<char, 96> text{};     // human-readable, NUL-terminated
  // Order of the event, from 1, increasing across a run (a reset goes on counting). A threaded
  // loop's snapshot carries every event its reader may not have taken yet, so a reader that took
  // an earlier snapshot can meet an event again: it keeps the newest seq it took and skips the
  // rest (gui::Session::latest).
  uint64_t seq = 0;
};

struct Snapshot {
  int64_t tick = 0;                // ticks completed
  double time = 0.0;               // simulation time [s]
  std::vector<float> x;            // 3 * particles: positions [m], float for the GPU
  DrawList draw;                   // instrument geometry recorded by Tool::draw
  std::vector<ToolReadout> tools;  // one per tool, in Simulation::tools() order
  std::vector<SnapshotEvent> events;   // since the previous published snapshot
  uint64_t state_hash = 0;         // hash of the full simulation state at this tick (0 = not computed)
  bool faulted = false;            // physics stopped on a numerical fault
  std::array<char, 160> fault{};   // its description (particle and time), NUL-terminated
};

}  // namespace ps
