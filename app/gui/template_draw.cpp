// The template drawn by the trainee window with ImGui (template_view.h): over the TRUS images and
// in the 3D view. Geometry from app/frames/template_overlay.h; only screen placement and styling
// here.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app/gui/template_view.h"
#include "engine/dosimetry/template_grid.h"

namespace ps::gui {

namespace {

constexpr ImU32 kWhite = IM_COL32(255, 255, 255, 255), kShadow = IM_COL32(0, 0, 0, 220);
constexpr ImU32 kAmber = IM_COL32(255, 205, 75, 255), kDone = IM_COL32(140, 150, 145, 255), kOffPlan = IM_COL32(90, 220, 255, 255);

ImU32 plan_colour(int alpha) { return IM_COL32(frames::kPlanRgb[0], frames::kPlanRgb[1], frames::kPlanRgb[2], alpha); }

ImU32 status_colour(frames::HoleStatus st, int alpha) {
  switch (st) {
    case frames::HoleStatus::Partial: return (kAmber & ~IM_COL32_A_MASK) | (static_cast<ImU32>(alpha) << IM_COL32_A_SHIFT);
    case frames::HoleStatus::Done: return (kDone & ~IM_COL32_A_MASK) | (static_cast<ImU32>(alpha) << IM_COL32_A_SHIFT);
    case frames::HoleStatus::Pending: break;
  }
  return plan_colour(alpha);
}

// text centred on (x, y) with a 1 px dark outline, so it reads on speckle and on the 3D scene
void label(ImDrawList* dl, float x, float y, const std::string& t, float size, ImU32 col) {
  ImFont* f = ImGui::GetFont();
  const ImVec2 ts = f->CalcTextSizeA(size, 1e9f, 0.0f, t.c_str());
  const ImVec2 p(std::round(x - 0.5f * ts.x), std::round(y - 0.5f * ts.y));
  for (const ImVec2 d : {ImVec2(-1, 0), ImVec2(1, 0), ImVec2(0, -1), ImVec2(0, 1)})
    dl->AddText(f, size, ImVec2(p.x + d.x, p.y + d.y), kShadow, t.c_str());
  dl->AddText(f, size, p, col, t.c_str());
}

// text from its top-left corner, outlined as label()
void corner_text(ImDrawList* dl, ImVec2 at, const char* t, ImU32 col) {
  for (const ImVec2 d : {ImVec2(-1, 0), ImVec2(1, 0), ImVec2(0, -1), ImVec2(0, 1)}) dl->AddText(ImVec2(at.x + d.x, at.y + d.y), kShadow, t);
  dl->AddText(at, col, t);
}

ImVec2 to_screen(const frames::ImageCrop& c, const frames::ImagePoint& p) {
  const frames::ImagePoint v = c.to_view(p);
  return ImVec2(static_cast<float>(v.x), static_cast<float>(v.y));
}

}  // namespace

void draw_transverse_template(ImDrawList* dl, const TemplateView& g, const frames::HoleMarks& marks, const frames::ImageCrop& crop,
                              int col, int row) {
  const float font = ImGui::GetFontSize();
  const float pitch = static_cast<float>(marks.pitch_px * crop.side / crop.size);  // on the screen [px]
  // the half-step labels (a, 1.5, ...) only where they fit between the whole ones at the font's own
  // size (ImGui's bitmap font turns to mush when scaled down): the TRUS panel's zoomed view has
  // ~13 px between holes, so it shows the capitals and whole numbers, as many TRUS units print them
  const bool halves = pitch >= 1.5f * font;
  for (const frames::GridLabel& l : frames::grid_labels(marks, g.cols, g.rows)) {
    if (!l.whole && !halves) continue;
    const ImVec2 at = to_screen(crop, l.at);
    label(dl, at.x, at.y, l.text, font, l.whole ? kWhite : IM_COL32(200, 200, 200, 255));
  }
  const float r = std::clamp(0.3f * pitch, 2.5f, 6.0f);
  for (size_t i = 0; i < marks.holes.size(); ++i) {
    const frames::TemplateHole& h = marks.holes[i];
    const ImVec2 c = to_screen(crop, marks.at[i]);
    const int seeds = g.seeds_in(h.col, h.row);
    if (const frames::PlannedHole* p = g.planned(h.col, h.row)) {
      const frames::HoleStatus st = g.status(*p);
      if (st == frames::HoleStatus::Done) dl->AddCircleFilled(c, r, status_colour(st, 230));
      else dl->AddCircle(c, r, status_colour(st, 255), 12, 1.5f);
    } else if (seeds > 0) {
      dl->AddCircleFilled(c, 0.6f * r, kOffPlan);
    }
    if (h.col == col && h.row == row) {
      dl->AddCircle(c, r + 3.0f, kShadow, 16, 3.0f);
      dl->AddCircle(c, r + 3.0f, kWhite, 16, 1.5f);
    }
  }
}

void draw_sagittal_plan(ImDrawList* dl, const TemplateView& g, const dosimetry::PixelPlane& plane, const frames::ImageCrop& view,
                        int col, int row) {
  const int i = g.index(col, row);
  if (i < 0) return;
  const frames::TemplateHole& h = g.holes[i];
  const std::string name = dosimetry::template_hole_label(col, row);
  const float font = ImGui::GetFontSize();
  double off_mm = 0.0;
  frames::plane_pixel(plane, h.entry, &off_mm);  // the line runs along the probe axis: as far off all along
  const ImVec2 corner(static_cast<float>(view.ox) + 4.0f, static_cast<float>(view.oy) + 2.0f);
  if (std::abs(off_mm) > 0.5e3 * g.pitch) {
    char t[64];
    std::snprintf(t, sizeof t, "%s: %.1f mm off this plane", name.c_str(), std::abs(off_mm));
    corner_text(dl, corner, t, IM_COL32(220, 220, 220, 255));
    return;
  }
  const frames::PlannedHole* p = g.planned(col, row);
  const double depth = p ? 1e-3 * p->depth_mm : 0.0;
  // the hole's line, dashed every 2.5 mm from the template to the planned depth (or across the
  // image without a plan)
  const double end = p ? depth : 0.15;
  for (double s = 0.0; s < end; s += 5e-3) {
    const ImVec2 a = to_screen(view, frames::plane_pixel(plane, h.entry + s * h.direction));
    const ImVec2 b = to_screen(view, frames::plane_pixel(plane, h.entry + std::min(s + 2.5e-3, end) * h.direction));
    dl->AddLine(a, b, plan_colour(p ? 200 : 110), 1.5f);
  }
  char t[64];
  if (!p) {
    std::snprintf(t, sizeof t, "%s: no planned needle", name.c_str());
    corner_text(dl, corner, t, IM_COL32(220, 220, 220, 255));
    return;
  }
  for (double sd : p->seeds_mm) dl->AddCircleFilled(to_screen(view, frames::plane_pixel(plane, h.entry + 1e-3 * sd * h.direction)), 2.5f, plan_colour(255));
  // the planned depth: a tick across the line and its figure beside it
  const ImVec2 tip = to_screen(view, frames::plane_pixel(plane, h.entry + depth * h.direction));
  const ImVec2 back = to_screen(view, frames::plane_pixel(plane, h.entry + (depth - 5e-3) * h.direction));
  ImVec2 d(tip.x - back.x, tip.y - back.y);
  const float n = std::max(1e-3f, std::hypot(d.x, d.y));
  d = ImVec2(d.x / n, d.y / n);
  const ImVec2 across(-d.y * 7.0f, d.x * 7.0f);
  dl->AddLine(ImVec2(tip.x - across.x, tip.y - across.y), ImVec2(tip.x + across.x, tip.y + across.y), plan_colour(255), 2.0f);
  // the figure above the tick, kept inside the image (the planned depth is often near its edge)
  std::snprintf(t, sizeof t, "%.0f mm", p->depth_mm);
  const float half = 0.5f * ImGui::GetFont()->CalcTextSizeA(font, 1e9f, 0.0f, t).x + 2.0f;
  const float lx = std::clamp(tip.x, static_cast<float>(view.ox) + half, static_cast<float>(view.ox + view.side) - half);
  label(dl, lx, tip.y - 14.0f, t, font, plan_colour(255));
  std::snprintf(t, sizeof t, "%s: planned depth %.1f mm", name.c_str(), p->depth_mm);
  corner_text(dl, corner, t, plan_colour(255));
}

void draw_template_3d(ImDrawList* dl, const TemplateView& g, const Eigen::Matrix4f& vp, float x, float y, float w, float h, int col,
                      int row) {
  if (!g.has_template()) return;
  // world [m] -> screen; false behind the camera
  auto project = [&](const Vec3& p, ImVec2& out) {
    const Eigen::Vector4f c = vp * Eigen::Vector4f(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), 1.0f);
    if (!(c.w() > 1e-6f)) return false;
    out = ImVec2(x + (0.5f + 0.5f * c.x() / c.w()) * w, y + (0.5f - 0.5f * c.y() / c.w()) * h);
    return true;
  };
  const auto entry = [&](int c, int r) -> const Vec3* {
    const int i = g.index(c, r);
    return i >= 0 ? &g.holes[i].entry : nullptr;
  };
  const Vec3 *a0 = entry(0, 0), *a1 = entry(0, 1), *b0 = entry(1, 0);
  if (!a0 || !a1 || !b0) return;
  const Vec3 up = *a1 - *a0, right = *b0 - *a0;  // one spacing along a column, along a row
  ImVec2 s0, s1;
  const float font = ImGui::GetFontSize();
  // the half-steps when a full-size label fits between the whole ones (as on the TRUS image)
  const bool halves = project(*a0, s0) && project(*a1, s1) && std::hypot(s1.x - s0.x, s1.y - s0.y) >= 1.5f * font;
  ImVec2 at;
  for (int c = 0; c < g.cols; ++c)
    if (const Vec3* e = entry(c, 0); e && (c % 2 == 0 || halves) && project(*e - 1.6 * up, at))
      label(dl, at.x, at.y, dosimetry::template_column_label(c), font, kWhite);
  for (int r = 0; r < g.rows; ++r)
    if (const Vec3* e = entry(0, r); e && (r % 2 == 0 || halves) && project(*e - 1.6 * right, at))
      label(dl, at.x, at.y, dosimetry::template_row_label(r), font, kWhite);
  // the planned needles: their line to the planned depth and their seeds
  for (const frames::PlannedHole& p : g.plan) {
    const int i = g.index(p.col, p.row);
    if (i < 0) continue;
    const frames::TemplateHole& th = g.holes[i];
    const bool picked = p.col == col && p.row == row;
    const frames::HoleStatus st = g.status(p);
    const int alpha = picked ? 255 : st == frames::HoleStatus::Done ? 70 : 130;
    ImVec2 a, b;
    if (project(th.entry, a) && project(th.entry + 1e-3 * p.depth_mm * th.direction, b))
      dl->AddLine(a, b, status_colour(st, alpha), picked ? 2.0f : 1.0f);
    if (st == frames::HoleStatus::Done) continue;  // its seeds are in: the scene shows them
    for (double sd : p.seeds_mm)
      if (project(th.entry + 1e-3 * sd * th.direction, b)) dl->AddCircleFilled(b, picked ? 2.5f : 1.8f, status_colour(st, alpha));
  }
  if (const Vec3* e = entry(col, row); e && project(*e, at)) {
    dl->AddCircle(at, 5.0f, kShadow, 12, 3.0f);
    dl->AddCircle(at, 5.0f, kWhite, 12, 1.5f);
    label(dl, at.x + 16.0f, at.y - 10.0f, dosimetry::template_hole_label(col, row), font, kWhite);
  }
}

}  // namespace ps::gui
