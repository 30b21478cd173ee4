// `prostatesim edit [SCENARIO]`: the instructor's scenario editor window (GLFW + Dear ImGui around
// the trainee app's renderer, render/). Every change goes through EditorCommands
// (app/editor/editor_commands.h); this file only lays out widgets, the 3D view (picking and
// dragging lesions, targets and seeds' needles in the view plane) and the in-place preview.
// Scripted use (tests, batch fixes): --set KEY=VALUE edits applied at start through the same
// command path, --save writes the file, --preview S runs the in-place preview S simulated seconds
// (and prints its state hash), --frames N closes after N frames, --screenshot PNG.
#pragma once
#include <string>
#include <vector>

namespace ps::editor {

struct EditorArgs {
  std::string scenario;            // "" : the window opens with an empty Open field
  std::vector<std::string> sets;   // KEY=VALUE (key path = YAML value)
  bool save = false;               // save after the --set edits (atomically)
  std::string save_as;             // save to this path instead
  int frames = -1;                 // close after this many frames (-1: when the user closes)
  std::string screenshot;          // PNG of the last frame
  double preview_s = 0.0;          // run the preview this long [s] at the first frame, print its state hash
};

// Runs the window until it closes. Exit code: 0, 2 when a --set edit or --save was refused (the
// reason printed as file:line:field), 4 when no window can be opened.
int run_editor(const EditorArgs& a);

}  // namespace ps::editor
