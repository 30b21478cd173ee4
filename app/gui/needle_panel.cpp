// The needles' panel: which needle is driven, its speed, advance / stop / retract, the gun and the
// seeds, and the active needle's depth and axial force.
#include <imgui.h>

#include "app/gui/session.h"
#include "app/gui/tool_panels.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/tool_kind.h"

namespace ps::gui {

void needle_controls(Session& s, const Snapshot& snap, ToolPanelState& st) {
  if (s.needle_count() <= 0) return;
  NeedlePanelState& n = st.needle;
  const ToolReadout* active = nullptr;
  for (const auto& t : snap.tools)
    if (t.kind == tool_kind_index(NeedleTool::kind()) && (t.active || !active)) active = &t;
  ImGui::Text("Needle");
  if (ImGui::BeginCombo("active", s.needle_name(n.needle).c_str())) {
    for (int i = 0; i < s.needle_count(); ++i)
      if (ImGui::Selectable(s.needle_name(i).c_str(), i == n.needle)) { n.needle = i; s.select(i); }
    ImGui::EndCombo();
  }
  ImGui::SliderFloat("speed [mm/s]", &n.speed_mm_s, 0.5f, 50.0f);
  if (ImGui::Button("Advance")) s.advance(n.needle, n.speed_mm_s * 1e-3);
  ImGui::SameLine();
  if (ImGui::Button("Stop")) s.advance(n.needle, 0.0);
  ImGui::SameLine();
  if (ImGui::Button("Retract")) s.advance(n.needle, -n.speed_mm_s * 1e-3);
  if (ImGui::Button("Fire gun")) s.fire(n.needle);
  ImGui::SameLine();
  if (ImGui::Button("Deposit seed")) s.seed(n.needle);
  if (active) ImGui::Text("depth %.1f mm   force %.2f N", active->depth * 1e3, active->force);
  ImGui::Separator();
}

}  // namespace ps::gui
