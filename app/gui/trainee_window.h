// The trainee window, registered as the window frontend of `prostatesim run` (app/core/run_session.h):
// GLFW + Dear ImGui around the 3D view of render/. The physics runs on its own thread
// (engine/realtime/physics_loop.h); the window reads the snapshots it publishes and pushes
// commands, so the physics never waits for the UI. Panels: instruments (probe pose, needle
// selection, speed, advance / retract / fire / seed), live force-versus-depth of the active
// needle, ultrasound (placeholder until engine/ultrasound lands), event log, timing (tick rate,
// real-time factor, frame time), view (presets, organ opacity, displacement colours, force
// arrows), help overlay with the bindings; open a scenario, restart, pause, record. A scenario
// that fails to compile is shown (file:line:field) and the last good scene keeps running.
// A simulation fault is shown over the 3D view with "Save last good state" and "Restart scene";
// "Load state" (instruments panel) goes on from a saved state file of the scenario.
// Test hooks: PROSTATESIM_SCREENSHOT=FILE saves the window (panels included) as a PNG when it
// closes (with `run --duration S` it closes by itself at the end); PROSTATESIM_CLICKS="A;B"
// clicks the buttons labelled A, then B, as soon as each is shown, through ImGui's mouse input
// (tests/app/window_recovery_test.cpp).
#pragma once
#include "app/core/run_session.h"

namespace ps::gui {

// Runs the window until closed (or the run's end tick); returns the exit code (0; 4 when no
// OpenGL 3.3 window can be created).
int run_window(app::RunSession& run);

}  // namespace ps::gui
