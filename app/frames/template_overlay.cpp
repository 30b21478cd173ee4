#include "app/frames/template_overlay.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "app/plot/canvas.h"
#include "engine/dosimetry/template_grid.h"
#include "engine/tools/probe/probe_geometry.h"

namespace ps::frames {

std::vector<TemplateHole> template_holes_from_draw(const DrawList& draw, int cols, int rows, const Vec3& axis) {
  std::vector<TemplateHole> out;
  if (cols <= 0 || rows <= 0) return out;
  for (const DrawSphere& s : draw.spheres)
    if (s.role == DrawRole::TemplateGrid) {
      const int k = static_cast<int>(out.size());
      out.push_back({k % cols, k / cols, s.centre, axis.normalized()});
    }
  if (static_cast<int>(out.size()) != cols * rows) out.clear();
  return out;
}

ImagePoint plane_pixel(const dosimetry::PixelPlane& pl, const Vec3& p, double* off_plane_mm) {
  const Vec3 v = 1e3 * p - pl.p00_mm;  // [mm]
  const double cc = pl.dcol_mm.squaredNorm(), rr = pl.drow_mm.squaredNorm();
  if (off_plane_mm) {
    const Vec3 n = pl.dcol_mm.cross(pl.drow_mm);
    *off_plane_mm = n.norm() > 0 ? v.dot(n.normalized()) : 0.0;
  }
  // the columns and rows of a PixelPlane are perpendicular (a plane frame's right and up)
  return {cc > 0 ? v.dot(pl.dcol_mm) / cc : 0.0, rr > 0 ? v.dot(pl.drow_mm) / rr : 0.0};
}

std::optional<ImagePoint> line_crossing_pixel(const dosimetry::PixelPlane& pl, const Vec3& entry, const Vec3& direction) {
  const Vec3 n = pl.dcol_mm.cross(pl.drow_mm);
  const double dn = direction.dot(n);
  if (!(std::abs(dn) > 1e-9 * n.norm() * direction.norm())) return std::nullopt;
  const double s = (1e-3 * pl.p00_mm - entry).dot(n) / dn;  // [m] along the line
  return plane_pixel(pl, entry + s * direction);
}

namespace {

// index of hole (col, row) in `holes`, -1 when absent
int hole_index(const std::vector<TemplateHole>& holes, int col, int row) {
  for (size_t i = 0; i < holes.size(); ++i)
    if (holes[i].col == col && holes[i].row == row) return static_cast<int>(i);
  return -1;
}

double distance(const ImagePoint& a, const ImagePoint& b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace

HoleMarks transverse_hole_marks(const dosimetry::PixelPlane& plane, const std::vector<TemplateHole>& holes) {
  HoleMarks m;
  for (const TemplateHole& h : holes) {
    const std::optional<ImagePoint> p = line_crossing_pixel(plane, h.entry, h.direction);
    if (!p) continue;
    m.holes.push_back(h);
    m.at.push_back(*p);
  }
  // the spacing: the nearest pair of neighbours in a row or a column (all holes are that far apart)
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < m.holes.size() && !std::isfinite(best); ++i) {
    for (const auto& [dc, dr] : {std::pair{1, 0}, std::pair{0, 1}}) {
      const int j = hole_index(m.holes, m.holes[i].col + dc, m.holes[i].row + dr);
      if (j >= 0) best = std::min(best, distance(m.at[i], m.at[j]));
    }
  }
  m.pitch_px = std::isfinite(best) ? best : 0.0;
  return m;
}

int pick_hole(const HoleMarks& marks, double x, double y) {
  int best = -1;
  double bd = 0.5 * marks.pitch_px;
  for (size_t i = 0; i < marks.at.size(); ++i) {
    const double d = distance(marks.at[i], {x, y});
    if (d <= bd) bd = d, best = static_cast<int>(i);
  }
  return best;
}

ImageCrop whole_image(int n, double ox, double oy, double side) {
  ImageCrop c;
  c.n = n;
  c.x0 = c.y0 = -0.5;  // the outer edges of the edge pixels
  c.size = n;
  c.ox = ox, c.oy = oy, c.side = side;
  return c;
}

ImageCrop template_crop(const HoleMarks& m, int n, double ox, double oy, double side) {
  ImageCrop c = whole_image(n, ox, oy, side);
  if (m.at.empty() || !(m.pitch_px > 0)) return c;
  double xmin = m.at[0].x, xmax = xmin, ymin = m.at[0].y, ymax = ymin;
  for (const ImagePoint& p : m.at) {
    xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
  }
  // the labels are left of column A and below row 1 (grid_labels)
  xmin -= 2.0 * m.pitch_px, ymax += 1.6 * m.pitch_px;
  xmax += 0.75 * m.pitch_px, ymin -= 0.75 * m.pitch_px;
  const double size = std::max(xmax - xmin, ymax - ymin);
  if (!(size < n)) return c;
  c.size = size;
  c.x0 = std::clamp(0.5 * (xmin + xmax) - 0.5 * size, -0.5, n - 0.5 - size);
  c.y0 = std::clamp(0.5 * (ymin + ymax) - 0.5 * size, -0.5, n - 0.5 - size);
  return c;
}

std::vector<GridLabel> grid_labels(const HoleMarks& m, int cols, int rows) {
  std::vector<GridLabel> out;
  auto at = [&](int c, int r) -> const ImagePoint* {
    const int i = hole_index(m.holes, c, r);
    return i >= 0 ? &m.at[i] : nullptr;
  };
  // one spacing beyond the edge hole, away from its neighbour: below row 0, left of column 0
  for (int c = 0; c < cols; ++c) {
    const ImagePoint *a = at(c, 0), *b = at(c, 1);
    if (!a || !b) continue;
    out.push_back({dosimetry::template_column_label(c), {2 * a->x - b->x, 2 * a->y - b->y}, c % 2 == 0});
  }
  for (int r = 0; r < rows; ++r) {
    const ImagePoint *a = at(0, r), *b = at(1, r);
    if (!a || !b) continue;
    out.push_back({dosimetry::template_row_label(r), {2 * a->x - b->x, 2 * a->y - b->y}, r % 2 == 0});
  }
  return out;
}

std::vector<PlannedHole> planned_holes(const ScenarioSpec& spec) {
  // a needle through a hole: within 1 mm of its line (an 18 G needle is 1.27 mm across)
  constexpr double kThroughHole = 1e-3;  // [m]
  std::vector<PlannedHole> out;
  if (!spec.probe || !spec.probe->has_template) return out;
  const ProbeSpec& ps = *spec.probe;
  const RectalFrame rf = rectal_frame(ps);
  std::vector<NeedlePath> lines;
  for (int r = 0; r < ps.template_rows; ++r)
    for (int c = 0; c < ps.template_cols; ++c) lines.push_back(template_hole_path(ps, rf, ps.pose, c, r));
  const double cos_parallel = std::cos(1.0 * 3.14159265358979323846 / 180.0);  // within 1 degree
  const auto& needles = spec.needles.needles;
  for (size_t i = 0; i < needles.size(); ++i) {
    const NeedleSpec& n = needles[i];
    if (n.seed_depths.empty() || !n.guide.empty()) continue;
    const Vec3 d = n.direction.normalized();
    int best = -1;
    double bd = kThroughHole;
    for (size_t k = 0; k < lines.size(); ++k) {
      if (d.dot(lines[k].direction) < cos_parallel) continue;
      const Vec3 v = n.start - lines[k].entry;
      const double off = (v - v.dot(lines[k].direction) * lines[k].direction).norm();
      if (off < bd) bd = off, best = static_cast<int>(k);
    }
    if (best < 0) continue;
    const NeedlePath& h = lines[best];
    double deepest = 0.0;
    for (const NeedleScriptPoint& p : n.script) deepest = std::max(deepest, p.depth);
    for (double s : n.seed_depths) deepest = std::max(deepest, s);
    PlannedHole ph;
    ph.col = best % ps.template_cols;
    ph.row = best / ps.template_cols;
    ph.label = dosimetry::template_hole_label(ph.col, ph.row);
    ph.needle = static_cast<int>(i);
    ph.needle_name = n.name;
    auto past_template_mm = [&](double depth) { return 1e3 * (n.start + depth * d - h.entry).dot(h.direction); };
    ph.depth_mm = past_template_mm(deepest);
    for (double s : n.seed_depths) ph.seeds_mm.push_back(past_template_mm(s));
    out.push_back(std::move(ph));
  }
  return out;
}

int find_planned(const std::vector<PlannedHole>& plan, int col, int row) {
  for (size_t i = 0; i < plan.size(); ++i)
    if (plan[i].col == col && plan[i].row == row) return static_cast<int>(i);
  return -1;
}

std::vector<int> seeds_per_hole(const std::vector<TemplateHole>& holes, const std::vector<Vec3>& seeds, double pitch) {
  std::vector<int> n(holes.size(), 0);
  for (const Vec3& s : seeds) {
    int best = -1;
    double bd = 0.5 * pitch;
    for (size_t k = 0; k < holes.size(); ++k) {
      const Vec3 v = s - holes[k].entry;
      const double off = (v - v.dot(holes[k].direction) * holes[k].direction).norm();
      if (off <= bd) bd = off, best = static_cast<int>(k);
    }
    if (best >= 0) ++n[best];
  }
  return n;
}

std::vector<Vec3> drawn_seeds(const DrawList& draw) {
  std::vector<Vec3> out;
  for (const DrawCapsule& c : draw.capsules)
    if (c.role == DrawRole::Seed) out.push_back(0.5 * (c.a + c.b));
  for (const DrawSphere& s : draw.spheres)
    if (s.role == DrawRole::Seed) out.push_back(s.centre);
  return out;
}

HoleStatus hole_status(int deposited, int planned) {
  if (deposited <= 0) return HoleStatus::Pending;
  return deposited >= planned ? HoleStatus::Done : HoleStatus::Partial;
}

const char* hole_status_name(HoleStatus s) {
  switch (s) {
    case HoleStatus::Pending: return "pending";
    case HoleStatus::Partial: return "partial";
    case HoleStatus::Done: return "done";
  }
  return "?";
}

namespace {

// Plots into a 1- or 3-channel image (rows top-down); off-image pixels are skipped.
struct Raster {
  std::vector<uint8_t>& px;
  int w, h, ch;
  void put(int x, int y, const uint8_t* c) {
    if (x < 0 || y < 0 || x >= w || y >= h) return;
    uint8_t* p = &px[(static_cast<size_t>(y) * w + x) * ch];
    for (int k = 0; k < ch; ++k) p[k] = c[k];
  }
};

// the grid over one image: rings round the planned holes, the labels outlined
void draw_template(Raster& img, const HoleMarks& marks, int cols, int rows, const std::vector<PlannedHole>& plan,
                   const uint8_t* plan_colour, const uint8_t* white, const uint8_t* dark) {
  for (size_t i = 0; i < marks.holes.size(); ++i) {
    if (find_planned(plan, marks.holes[i].col, marks.holes[i].row) < 0) continue;
    // a ring of radius 3 px round the imager's cross (5 px): the plan's holes stand out
    const int cx = static_cast<int>(std::lround(marks.at[i].x)), cy = static_cast<int>(std::lround(marks.at[i].y));
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        const int r2 = dx * dx + dy * dy;
        if (r2 >= 7 && r2 <= 12) img.put(cx + dx, cy + dy, plan_colour);
      }
  }
  // the half-step labels when a label (5 px wide at scale 1) and a gap fit between neighbours
  const int scale = std::max(1, std::min(img.w, img.h) / 600 + 1);
  const bool halves = marks.pitch_px >= 8.0 * scale;
  for (const GridLabel& l : grid_labels(marks, cols, rows)) {
    if (!l.whole && !halves) continue;
    const int tw = plot::Canvas::text_width(l.text, scale), th = plot::Canvas::text_height(scale);
    plot::Canvas glyphs(tw + 2, th + 2, {0, 0, 0});
    glyphs.text(1, 1, l.text, {255, 255, 255}, scale);
    const int x0 = static_cast<int>(std::lround(l.at.x - 0.5 * tw)) - 1, y0 = static_cast<int>(std::lround(l.at.y - 0.5 * th)) - 1;
    // the outline first (every pixel next to a glyph pixel), then the glyphs over it
    for (int y = 0; y < glyphs.height(); ++y)
      for (int x = 0; x < glyphs.width(); ++x) {
        bool near = false;
        for (int dy = -1; dy <= 1 && !near; ++dy)
          for (int dx = -1; dx <= 1 && !near; ++dx) {
            const int u = x + dx, v = y + dy;
            near = u >= 0 && v >= 0 && u < glyphs.width() && v < glyphs.height() && glyphs.at(u, v).r > 127;
          }
        if (near) img.put(x0 + x, y0 + y, dark);
      }
    for (int y = 0; y < glyphs.height(); ++y)
      for (int x = 0; x < glyphs.width(); ++x)
        if (glyphs.at(x, y).r > 127) img.put(x0 + x, y0 + y, white);
  }
}

}  // namespace

void draw_template_gray(std::vector<uint8_t>& gray, int w, int h, const HoleMarks& marks, int cols, int rows,
                        const std::vector<PlannedHole>& plan) {
  Raster r{gray, w, h, 1};
  const uint8_t ring[1] = {255}, white[1] = {255}, dark[1] = {0};
  draw_template(r, marks, cols, rows, plan, ring, white, dark);
}

void draw_template_rgb(std::vector<uint8_t>& rgb, int w, int h, const HoleMarks& marks, int cols, int rows,
                       const std::vector<PlannedHole>& plan) {
  Raster r{rgb, w, h, 3};
  const uint8_t ring[3] = {kPlanRgb[0], kPlanRgb[1], kPlanRgb[2]}, white[3] = {255, 255, 255}, dark[3] = {0, 0, 0};
  draw_template(r, marks, cols, rows, plan, ring, white, dark);
}

}  // namespace ps::frames
