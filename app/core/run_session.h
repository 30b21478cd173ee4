// Seams between `prostatesim run` / `prostatesim replay` (app/cmd_run.cpp, app/cmd_replay.cpp)
// and the frontends that plug into them without touching those commands: the trainee window
// (render/, GLFW + ImGui) and the headless PNG frame writer. A frontend registers itself in
// main() before the command line is parsed (one line each):
//   ps::app::register_window_frontend(&run_window);
//   ps::app::register_replay_frames({&add_frame_options, &frames_wanted, &write_frames});
// Neither the commands nor engine/realtime know anything of GL.
#pragma once
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/physics_loop.h"
#include "engine/realtime/recording.h"
#include "engine/realtime/script.h"
#include "engine/realtime/state_file.h"
#include "engine/sim/scene.h"
#include "haptics/device_source.h"
#include "haptics/mouse_keyboard.h"

namespace ps::app {

// A live run, handed to the window frontend once the physics thread runs.
struct RunSession {
  Scene& scene;
  PhysicsLoop& loop;               // snapshots (update_snapshot/snapshot), queue() + next_tick()
                                   // for commands, pause/resume/single_step/reset/set_factor
  const Script* script = nullptr;  // --script, if any (already feeding the loop)
  int64_t end_tick = -1;           // --duration in ticks, -1: until the window closes
  std::string scenario_path;
  // Mouse and keyboard as a device (docs/realtime.md bindings): the window feeds its events
  // (drag, key) here from the UI thread; the physics thread polls it. Null when another device
  // (--device spacemouse) or a script drives the needle.
  haptics::MouseKeyboardDevice* mouse = nullptr;
  haptics::DeviceSource* device = nullptr;  // status() after a disconnect, active needle
  bool records = false;            // --record: the session is recorded from its start (no state loads)
};
// Runs the window's event loop until it closes; returns the exit code. The loop is stopped,
// the recording finished and the hash printed by cmd_run afterwards.
using WindowFrontend = int (*)(RunSession&);
void register_window_frontend(WindowFrontend f);
WindowFrontend window_frontend();  // null when no window frontend is linked

// A headless replay, handed to the frame writer (lock-step: no thread, no wall clock).
struct ReplaySession {
  Scene& scene;
  LockstepRunner& runner;          // advance_to(tick), snapshot()
  int64_t end_tick = 0;            // the replay's last tick
  std::string scenario_path;
};
struct ReplayFrames {
  void (*add_options)(CLI::App& replay) = nullptr;  // --out DIR --size WxH --fps N --views ... --force
  bool (*wanted)() = nullptr;                        // true when the frame options were given
  int (*run)(ReplaySession&) = nullptr;              // writes the frames; returns the exit code
};
void register_replay_frames(ReplayFrames f);
const ReplayFrames& replay_frames();

// Recovery helpers shared by run, replay and the window (run_session.cpp).
// Test hook --inject-fault: "nan@TICK" (a NaN put into particle 0 before that tick: a simulation
// fault) or "throw@TICK" (an exception in the loop: an internal error). InputError otherwise.
struct FaultInjection {
  int64_t tick = -1;
  bool internal = false;
};
FaultInjection parse_fault_injection(const std::string& spec);
// Writes the last good state (engine/realtime/state_file.h) with the scene's name and content
// hash, atomically, and says so on stderr.
void save_fault_state(const std::string& path, SavedState st, const Scene& scene);

}  // namespace ps::app
