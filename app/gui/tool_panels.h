// The trainee window's panels of each instrument kind, found by the kind (engine/tools/
// tool_kind.h): for every kind its scene holds, the window draws the controls this list gives on
// the left and the read-outs on the right. A kind with no entry here has no panel; a new kind adds
// its panel functions in its own file and one line to tool_panels().
#pragma once
#include <vector>

#include "app/gui/template_view.h"
#include "engine/contract/snapshot.h"
#include "engine/spec/scenario_spec.h"
#include "engine/tools/tool_kind.h"

namespace ps::gui {

class Session;

// The probe held as its handle: the pose the trainee commands (sliders, keys, Ctrl + drag / wheel),
// and its contact force on the rectal wall as the session metrics keep it (docs/metrics.md).
struct ProbePanelState {
  float insertion_mm = 0, roll_deg = 0, tilt_deg = 0, yaw_deg = 0;
  double peak_n = 0, above_s = 0, time = 0;
  void reset(const ProbePose& p);
  void command(Session& s) const;  // moves the probe to this pose
};

struct NeedlePanelState {
  int needle = 0;                  // selected needle index
  float speed_mm_s = 5.0f;         // advance speed [mm/s]
  int hole_col = -1, hole_row = -1;  // the template hole last picked (-1: none)
  TemplateView grid;               // the template, its plan and what is implanted (template_view.h)
};

// Picks template hole (col, row), as the hole list, the plan list and a click on the transverse
// image do: a hole with a planned needle of its own (preloaded with that hole's seeds) makes that
// needle the active one; the active needle is then aimed along the hole (Session::aim_hole).
void pick_template_hole(Session& s, NeedlePanelState& n, int col, int row);

// What the panels keep between frames (reset when a scene is loaded or restarted).
struct ToolPanelState {
  ProbePanelState probe;
  NeedlePanelState needle;
};

struct ToolPanel {
  const ToolKind* kind;
  void (*controls)(Session& s, const Snapshot& snap, ToolPanelState& st);  // left panel; may be null
  void (*readouts)(Session& s, const Snapshot& snap, ToolPanelState& st);  // right panel; may be null
};

// In the order the window shows them.
const std::vector<ToolPanel>& tool_panels();

// Each panel of the kinds the scene holds, in that order.
void draw_tool_controls(Session& s, const Snapshot& snap, ToolPanelState& st);
void draw_tool_readouts(Session& s, const Snapshot& snap, ToolPanelState& st);

// The panels of each kind (probe_panel.cpp, needle_panel.cpp, filling_panel.cpp).
void probe_controls(Session& s, const Snapshot& snap, ToolPanelState& st);
void needle_controls(Session& s, const Snapshot& snap, ToolPanelState& st);
void filling_readouts(Session& s, const Snapshot& snap, ToolPanelState& st);

}  // namespace ps::gui
