// The needles' panel: which needle is driven, its speed, advance / stop / retract, the gun and the
// seeds, the template hole it goes through (a scene whose probe carries a template: the holes by
// their clinical labels, engine/dosimetry/template_grid.h; picking one aims the needle along it,
// tip at the template, held), and the active needle's depth and axial force.
#include <imgui.h>

#include "app/gui/session.h"
#include "app/gui/tool_panels.h"
#include "engine/dosimetry/template_grid.h"
#include "engine/sim/scene.h"
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
  const auto& probe = s.scene().spec.probe;
  if (probe && probe->has_template) {
    // columns A a B b ... from the patient's right, rows 1 1.5 2 ... up from the probe
    const std::string shown = n.hole_col >= 0 ? dosimetry::template_hole_label(n.hole_col, n.hole_row) : "pick a hole";
    if (ImGui::BeginCombo("template hole", shown.c_str())) {
      for (int row = probe->template_rows - 1; row >= 0; --row)
        for (int col = 0; col < probe->template_cols; ++col) {
          const std::string label = dosimetry::template_hole_label(col, row);
          if (ImGui::Selectable(label.c_str(), col == n.hole_col && row == n.hole_row)) {
            n.hole_col = col;
            n.hole_row = row;
            s.aim_hole(n.needle, col, row);
          }
        }
      ImGui::EndCombo();
    }
  }
  if (active) ImGui::Text("depth %.1f mm   force %.2f N", active->depth * 1e3, active->force);
  ImGui::Separator();
}

}  // namespace ps::gui
