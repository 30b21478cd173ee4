// The filling's read-out: the target volume of the organ being filled (bladder_filling.yaml).
#include <imgui.h>

#include "app/gui/session.h"
#include "app/gui/tool_panels.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/tool_kind.h"

namespace ps::gui {

void filling_readouts(Session&, const Snapshot& snap, ToolPanelState&) {
  for (const ToolReadout& r : snap.tools)
    if (r.kind == tool_kind_index(FillingTool::kind()) && ImGui::CollapsingHeader("Filling", ImGuiTreeNodeFlags_DefaultOpen))
      ImGui::Text("target volume of the filled organ %.1f ml", r.value * 1e6);
}

}  // namespace ps::gui
