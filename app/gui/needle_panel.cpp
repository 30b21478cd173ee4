// The needles' panel: which needle is driven, its speed, advance / stop / retract, the gun and the
// seeds, the template hole it goes through (a scene whose probe carries a template: the holes by
// their clinical labels, engine/dosimetry/template_grid.h; picking one aims the needle along it,
// tip at the template, held), the scene's plan hole by hole with what is implanted, the picked
// hole's planned depth beside the needle's depth past the template, and the active needle's depth
// and axial force.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app/gui/session.h"
#include "app/gui/tool_panels.h"
#include "engine/dosimetry/template_grid.h"
#include "engine/sim/scene.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/tool_kind.h"

namespace ps::gui {

namespace {

ImVec4 status_colour(frames::HoleStatus st) {
  switch (st) {
    case frames::HoleStatus::Done: return ImVec4(0.55f, 0.60f, 0.58f, 1.0f);     // dimmed: nothing left to do
    case frames::HoleStatus::Partial: return ImVec4(1.0f, 0.80f, 0.30f, 1.0f);   // amber: seeds still to drop
    case frames::HoleStatus::Pending: break;
  }
  return ImVec4(frames::kPlanRgb[0] / 255.0f, frames::kPlanRgb[1] / 255.0f, frames::kPlanRgb[2] / 255.0f, 1.0f);
}

// The plan hole by hole: label, planned depth, seeds in / planned, status; a click picks the hole.
void plan_list(Session& s, NeedlePanelState& n) {
  const TemplateView& g = n.grid;
  int done = 0, seeds = 0, in = 0;
  for (const frames::PlannedHole& p : g.plan) {
    done += g.status(p) == frames::HoleStatus::Done;
    seeds += static_cast<int>(p.seeds_mm.size());
    in += std::min(g.seeds_in(p.col, p.row), static_cast<int>(p.seeds_mm.size()));
  }
  ImGui::TextWrapped("Plan: %d needles, %d seeds; %d needles done, %d seeds in", static_cast<int>(g.plan.size()), seeds, done, in);
  ImGui::BeginChild("plan holes", ImVec2(0, 118), true);
  for (const frames::PlannedHole& p : g.plan) {
    const frames::HoleStatus st = g.status(p);
    char line[96];
    std::snprintf(line, sizeof line, "%-5s %5.1f mm  %d/%d seeds  %s##%d", p.label.c_str(), p.depth_mm, g.seeds_in(p.col, p.row),
                  static_cast<int>(p.seeds_mm.size()), frames::hole_status_name(st), p.needle);
    ImGui::PushStyleColor(ImGuiCol_Text, status_colour(st));
    if (ImGui::Selectable(line, p.col == n.hole_col && p.row == n.hole_row)) pick_template_hole(s, n, p.col, p.row);
    ImGui::PopStyleColor();
  }
  ImGui::EndChild();
}

// The picked hole against its plan: planned depth and seeds, and how deep the active needle's tip
// is past the template along that hole, with the stepper's position (the probe's insertion).
void hole_readout(const Snapshot& snap, const NeedlePanelState& n, const ToolReadout* needle) {
  const TemplateView& g = n.grid;
  const int i = g.index(n.hole_col, n.hole_row);
  if (i < 0) return;
  const std::string label = dosimetry::template_hole_label(n.hole_col, n.hole_row);
  char line[200];
  int k = 0;
  if (const frames::PlannedHole* p = g.planned(n.hole_col, n.hole_row)) {
    std::string at;
    for (double d : p->seeds_mm) at += (at.empty() ? "" : ", ") + std::to_string(static_cast<int>(std::lround(d)));
    k = std::snprintf(line, sizeof line, "%s: planned depth %.1f mm, seeds %d (at %s mm)", label.c_str(), p->depth_mm,
                      static_cast<int>(p->seeds_mm.size()), at.c_str());
  } else {
    k = std::snprintf(line, sizeof line, "%s: no planned needle in this hole", label.c_str());
  }
  double stepper_mm = -1.0;
  for (const ToolReadout& t : snap.tools)
    if (t.carries & kCarriesImaging) stepper_mm = 1e3 * t.value;
  if (needle && k > 0 && k < static_cast<int>(sizeof line)) {
    const frames::TemplateHole& h = g.holes[i];
    const double depth_mm = 1e3 * (needle->tip - h.entry).dot(h.direction);  // the tip past the template along the hole
    k += std::snprintf(line + k, sizeof line - k, ", current depth %.1f mm", depth_mm);
    if (stepper_mm >= 0 && k < static_cast<int>(sizeof line)) std::snprintf(line + k, sizeof line - k, " (stepper position %.1f mm)", stepper_mm);
  }
  ImGui::TextWrapped("%s", line);
}

}  // namespace

void pick_template_hole(Session& s, NeedlePanelState& n, int col, int row) {
  n.hole_col = col;
  n.hole_row = row;
  if (const frames::PlannedHole* p = n.grid.planned(col, row); p && p->needle != n.needle && p->needle < s.needle_count()) {
    n.needle = p->needle;
    s.select(n.needle);
  }
  s.aim_hole(n.needle, col, row);
  std::printf("picked hole %s: needle '%s' aimed along it\n", dosimetry::template_hole_label(col, row).c_str(), s.needle_name(n.needle).c_str());
  std::fflush(stdout);
}

void needle_controls(Session& s, const Snapshot& snap, ToolPanelState& st) {
  if (s.needle_count() <= 0) return;
  NeedlePanelState& n = st.needle;
  n.grid.update(s, snap);
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
    // columns A a B b ... from the patient's right, rows 1 1.5 2 ... up from the probe; a click on
    // the transverse image picks the nearest hole too (the TRUS panel)
    const std::string shown = n.hole_col >= 0 ? dosimetry::template_hole_label(n.hole_col, n.hole_row) : "pick a hole";
    if (ImGui::BeginCombo("template hole", shown.c_str())) {
      for (int row = probe->template_rows - 1; row >= 0; --row)
        for (int col = 0; col < probe->template_cols; ++col) {
          const std::string label = dosimetry::template_hole_label(col, row);
          if (ImGui::Selectable(label.c_str(), col == n.hole_col && row == n.hole_row)) pick_template_hole(s, n, col, row);
        }
      ImGui::EndCombo();
    }
    if (!n.grid.plan.empty()) plan_list(s, n);
    hole_readout(snap, n, active);
  }
  if (active) ImGui::Text("depth %.1f mm   force %.2f N", active->depth * 1e3, active->force);
  ImGui::Separator();
}

}  // namespace ps::gui
