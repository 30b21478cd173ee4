// How the TRUS probe looks (Tool::draw): its capsule body, the biopsy guide channel on its
// anterior side with the planned needle path ahead of it (dashed), the brachytherapy template
// grid on the stepper (lines through the hole rows and columns, a dot per hole), and the tissue
// force on the probe as an arrow at its tip (2 mm per N).
#include "engine/tools/probe/probe.h"

namespace ps {

namespace {
constexpr double kArrowPerNewton = 2e-3;  // [m/N]
constexpr double kGuideLength = 40e-3;    // guide channel drawn behind its exit [m]
constexpr double kPathLength = 90e-3;     // planned path drawn ahead of the exit [m]
}  // namespace

void ProbeTool::draw(DrawSink& out, const Model&, const State&) const {
  const Rgba body{0.55f, 0.62f, 0.72f, 1.0f}, guide{0.30f, 0.34f, 0.40f, 1.0f};
  const Rgba path{0.55f, 0.95f, 0.55f, 1.0f}, grid{0.35f, 0.85f, 0.80f, 1.0f};
  const Rgba force{1.0f, 0.55f, 0.0f, 1.0f};
  const Capsule& c = frame_.capsule;
  out.capsule(c.back, c.tip, c.radius, body, DrawRole::Probe);
  if (spec_.has_guide) {
    const NeedlePath g = biopsy_guide();
    out.capsule(g.entry - kGuideLength * g.direction, g.entry, 1.6e-3, guide, DrawRole::Guide);
    for (double s = 0.0; s < kPathLength; s += 4e-3)  // dashes of 2 mm every 4 mm
      out.segment(g.entry + s * g.direction, g.entry + (s + 2e-3) * g.direction, path, DrawRole::Guide);
  }
  if (spec_.has_template) {
    const int nc = spec_.template_cols, nr = spec_.template_rows;
    for (int r = 0; r < nr; ++r)
      out.segment(template_hole(0, r).entry, template_hole(nc - 1, r).entry, grid, DrawRole::TemplateGrid);
    for (int col = 0; col < nc; ++col)
      out.segment(template_hole(col, 0).entry, template_hole(col, nr - 1).entry, grid, DrawRole::TemplateGrid);
    for (int r = 0; r < nr; ++r)
      for (int col = 0; col < nc; ++col) out.sphere(template_hole(col, r).entry, 0.5e-3, grid, DrawRole::TemplateGrid);
  }
  if (force_.norm() > 0.05) out.arrow(c.tip, kArrowPerNewton * force_, force, DrawRole::Force);
}

}  // namespace ps
