#include "app/gui/metrics_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "app/gui/tip_target.h"
#include "engine/metrics/score.h"
#include "engine/metrics/session_metrics.h"
#include "engine/metrics/sextant_map.h"
#include "engine/metrics/tracked_point.h"
#include "engine/tools/needle/needle_events.h"
#include "engine/tools/needle/needle.h"

namespace ps::gui {

namespace {

struct NeedleLive {
  std::string name;
  TrackedPoint target;
  bool has_target = false;
  double peak = 0.0;               // [N]
  int punctures = 0;
  uint32_t hits = 0;               // structure bits
  int entry = -1;                  // first component punctured: the route, not a hit
  int entry_punctures = 0;         // of the route this pass: a second one is a hit (session_metrics.cpp)
  TipTargetHold tip_target;        // app/gui/tip_target.h
};

struct Live {
  const Scene* scene = nullptr;
  std::vector<NeedleLive> needles;
  bool has_map = false;            // a needle with planned sites: the live 12-core map
  SextantMap map;
  std::vector<Vec3> x;             // positions of the snapshot [m]
  int64_t last_tick = -1;
};

void reset(Live& L, const Scene& sc) {
  L = Live{};
  L.scene = &sc;
  for (const NeedleSpec& n : sc.spec.needles.needles) {
    NeedleLive v;
    v.name = n.name;
    Vec3 aim = n.start;
    if (n.target) aim = *n.target;
    else if (!n.script.empty()) {
      double d = 0.0;
      for (const auto& q : n.script) d = std::max(d, q.depth);
      aim = n.start + d * n.direction.normalized();
    }
    if (n.target || !n.script.empty()) {
      v.target = track_point(*sc.model, aim);
      v.has_target = true;
    }
    L.needles.push_back(v);
    if (!n.planned_sites.empty()) {
      L.has_map = true;
      L.map = empty_sextant_map(n.planned_sites);
    }
  }
}

// The 12-core map as the biopsy form draws it: planned sites outlined, cored green (count), a
// core with lesion red (the report's map, engine/metrics/sextant_map.h, live).
void draw_map(const SextantMap& map) {
  ImGui::TextUnformatted("12-core map (R lat, R med | L med, L lat)");
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const float cw = 44.0f, ch = 22.0f, left = 40.0f;
  const char* rows[3] = {"base", "mid", "apex"};
  for (int r = 0; r < 3; ++r) {
    dl->AddText(ImVec2(p0.x, p0.y + r * ch + 4), IM_COL32(180, 180, 180, 255), rows[r]);
    for (int c = 0; c < 4; ++c) {
      const SextantCell& cell = map.cells[4 * r + c];
      const ImVec2 a(p0.x + left + c * cw + (c >= 2 ? 6.0f : 0.0f), p0.y + r * ch), b(a.x + cw - 3, a.y + ch - 3);
      if (cell.cores > 0) dl->AddRectFilled(a, b, cell.lesion ? IM_COL32(210, 60, 50, 255) : IM_COL32(70, 160, 80, 255));
      dl->AddRect(a, b, cell.planned ? IM_COL32(220, 220, 220, 255) : IM_COL32(90, 90, 90, 255));
      if (cell.cores > 0) {
        const std::string n = std::to_string(cell.cores);
        dl->AddText(ImVec2(a.x + cw / 2 - 6, a.y + 3), IM_COL32(255, 255, 255, 255), n.c_str());
      }
    }
  }
  ImGui::Dummy(ImVec2(left + 4 * cw + 8, 3 * ch + 2));
  if (map.off_map > 0) ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%d core(s) outside the gland", map.off_map);
}

}  // namespace

void metrics_panel(Session& s, const Snapshot& snap) {
  static Live L;
  const Scene& sc = s.scene();
  if (L.scene != &sc || snap.tick < L.last_tick) reset(L, sc);  // another scene, or restarted
  L.last_tick = snap.tick;
  const Model& m = *sc.model;
  if (L.needles.empty()) {
    ImGui::TextDisabled("no needles in this scenario");
    return;
  }
  // events: "<needle>: <kind> <component> at ..."
  for (const SnapshotEvent& e : s.new_events()) {
    if (e.tool != sc.tools.index<NeedleTool>()) continue;
    const auto kind = static_cast<NeedleEventKind>(e.kind);
    const std::string t = e.text.data();
    if (kind == NeedleEventKind::Core)  // a needle in the guide goes through its route again on the next pass
      for (NeedleLive& n : L.needles)
        if (t.rfind(n.name + ": ", 0) == 0) n.entry_punctures = 0;
    if (kind == NeedleEventKind::Core && L.has_map) {  // "...: core at 21.7 mm, 0.00 N [right mid medial, lesion]"
      const size_t open = t.rfind('[');
      if (open != std::string::npos) {
        const std::string site = t.substr(open + 1);
        const int k = sextant_cell(site);
        if (k < 0) ++L.map.off_map;
        else {
          ++L.map.cells[k].cores;
          L.map.cells[k].lesion |= site.find("lesion") != std::string::npos;
        }
      }
    }
    if (kind != NeedleEventKind::Puncture && kind != NeedleEventKind::BoneHit && kind != NeedleEventKind::Contact &&
        kind != NeedleEventKind::Urethra && kind != NeedleEventKind::GlandExit)
      continue;
    const size_t colon = t.find(": ");
    if (colon == std::string::npos) continue;
    for (NeedleLive& n : L.needles) {
      if (n.name != t.substr(0, colon)) continue;
      int comp = -1;
      for (size_t c = 0; c < m.components.size(); ++c)
        if (t.find(" " + m.components[c].name + " at ") != std::string::npos) comp = static_cast<int>(c);
      if (kind == NeedleEventKind::Puncture) {
        ++n.punctures;
        if (n.entry < 0) n.entry = comp;
        const bool route = comp == n.entry && ++n.entry_punctures <= 1;
        if (comp >= 0 && !route) n.hits |= structure_of(m.components[static_cast<size_t>(comp)]);
      }
      if (kind == NeedleEventKind::BoneHit) n.hits |= structure_of(m.components[static_cast<size_t>(std::max(comp, 0))]) | 8u;
      if (kind == NeedleEventKind::Urethra) n.hits |= 1u;
      if (kind == NeedleEventKind::GlandExit) n.hits |= 16u;  // structure bits as session_metrics.cpp
    }
  }
  const size_t np = snap.x.size() / 3;
  L.x.resize(np);
  for (size_t i = 0; i < np; ++i) L.x[i] = Vec3(snap.x[3 * i], snap.x[3 * i + 1], snap.x[3 * i + 2]);
  double sum = 0.0;
  int counted = 0;
  if (ImGui::BeginTable("live_metrics", 5, ImGuiTableFlags_RowBg)) {
    // explicit widths: fit-to-content columns start at zero width in the first frames
    const float cw = ImGui::CalcTextSize("0").x;
    ImGui::TableSetupColumn("needle", ImGuiTableColumnFlags_WidthFixed, 9 * cw);
    ImGui::TableSetupColumn("tip-target mm", ImGuiTableColumnFlags_WidthFixed, 13 * cw);
    ImGui::TableSetupColumn("peak N", ImGuiTableColumnFlags_WidthFixed, 7 * cw);
    ImGui::TableSetupColumn("punct.", ImGuiTableColumnFlags_WidthFixed, 6 * cw);
    ImGui::TableSetupColumn("hit", ImGuiTableColumnFlags_WidthStretch);
    ImGui::TableHeadersRow();
    int k = 0;
    for (NeedleLive& n : L.needles) {
      const ToolReadout* r = nullptr;
      int seen = 0;
      for (const ToolReadout& t : snap.tools)
        if ((t.carries & kCarriesInsertion) && seen++ == k) r = &t;
      ++k;
      if (r) n.peak = std::max(n.peak, r->force);
      ImGui::TableNextRow();
      ImGui::TableSetColumnIndex(0);
      ImGui::TextUnformatted(n.name.c_str());
      ImGui::TableSetColumnIndex(1);
      if (n.has_target && r && r->depth > 0.0 && np == static_cast<size_t>(m.particle_count())) {
        const double d = n.tip_target.update(r->depth, 1e3 * (r->tip - n.target.position(L.x)).norm());
        sum += d;
        ++counted;
        if (n.tip_target.held(r->depth)) ImGui::Text("%.1f deepest", d);
        else ImGui::Text("%.1f", d);
      } else if (n.has_target && n.tip_target.measured()) {  // drawn out of the tissue: its error stays
        sum += n.tip_target.at_deepest_mm;
        ++counted;
        ImGui::Text("%.1f deepest", n.tip_target.at_deepest_mm);
      } else {
        ImGui::TextDisabled("-");
      }
      ImGui::TableSetColumnIndex(2);
      ImGui::Text("%.2f", n.peak);
      ImGui::TableSetColumnIndex(3);
      ImGui::Text("%d", n.punctures);
      ImGui::TableSetColumnIndex(4);
      std::string hits;
      for (int b = 1; b <= 16; b <<= 1)
        if (n.hits & static_cast<uint32_t>(b)) hits += std::string(hits.empty() ? "" : ", ") + structure_name(b);
      if (hits.empty()) ImGui::TextDisabled("none");
      else ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%s", hits.c_str());
    }
    ImGui::EndTable();
  }
  if (L.has_map) draw_map(L.map);
  if (counted > 0) {
    const double mean = sum / counted;
    ImGui::Text("mean tip-target %.1f mm", mean);
    // the scale of Han et al. 2012: robot 1.0 mm, freehand urologists 9.0 mm
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    const float w = ImGui::GetContentRegionAvail().x - 10, y = p0.y + 14;
    auto X = [&](double mm) { return p0.x + 5 + w * static_cast<float>(std::clamp(mm / 12.0, 0.0, 1.0)); };
    dl->AddLine(ImVec2(X(0), y), ImVec2(X(12), y), IM_COL32(150, 150, 150, 255), 2.0f);
    dl->AddCircleFilled(ImVec2(X(1.0), y), 5, IM_COL32(60, 170, 80, 255));
    dl->AddText(ImVec2(X(1.0) - 12, y - 18), IM_COL32(60, 170, 80, 255), "robot 1");
    dl->AddCircleFilled(ImVec2(X(9.0), y), 5, IM_COL32(220, 60, 60, 255));
    dl->AddText(ImVec2(X(9.0) - 30, y - 18), IM_COL32(220, 60, 60, 255), "freehand 9");
    dl->AddTriangleFilled(ImVec2(X(mean), y + 4), ImVec2(X(mean) - 6, y + 14), ImVec2(X(mean) + 6, y + 14), IM_COL32(90, 140, 255, 255));
    ImGui::Dummy(ImVec2(w, 34));
    ImGui::TextDisabled("Han et al., J Urol 2012 (mm)");
  }
}

}  // namespace ps::gui
