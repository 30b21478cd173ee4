#include "app/gui/tool_panels.h"

#include "app/gui/session.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"

namespace ps::gui {

const std::vector<ToolPanel>& tool_panels() {
  static const std::vector<ToolPanel> panels = {
      {&ProbeTool::kind(), probe_controls, nullptr},
      {&NeedleTool::kind(), needle_controls, nullptr},
      {&FillingTool::kind(), nullptr, filling_readouts},
  };
  return panels;
}

void draw_tool_controls(Session& s, const Snapshot& snap, ToolPanelState& st) {
  for (const ToolPanel& p : tool_panels())
    if (p.controls && s.scene().tools.index_of(*p.kind) >= 0) p.controls(s, snap, st);
}

void draw_tool_readouts(Session& s, const Snapshot& snap, ToolPanelState& st) {
  for (const ToolPanel& p : tool_panels())
    if (p.readouts && s.scene().tools.index_of(*p.kind) >= 0) p.readouts(s, snap, st);
}

}  // namespace ps::gui
