#include "app/gui/template_view.h"

#include "app/gui/session.h"
#include "engine/sim/scene.h"
#include "engine/ultrasound/from_simulation.h"

namespace ps::gui {

void TemplateView::update(const Session& s, const Snapshot& snap) {
  const Scene& sc = s.scene();
  if (for_scene != &sc) {
    *this = TemplateView{};
    for_scene = &sc;
    if (sc.spec.probe && sc.spec.probe->has_template) {
      cols = sc.spec.probe->template_cols;
      rows = sc.spec.probe->template_rows;
      pitch = sc.spec.probe->template_pitch;
      plan = frames::planned_holes(sc.spec);
    }
  }
  if (cols <= 0 || snap.tick == tick) return;
  tick = snap.tick;
  us::ProbeView probe;
  if (!us::probe_view_from_snapshot(snap, probe)) return;  // keeps the last holes seen
  holes = frames::template_holes_from_draw(snap.draw, cols, rows, probe.axis);
  seeds = frames::seeds_per_hole(holes, frames::drawn_seeds(snap.draw), pitch);
}

int TemplateView::index(int col, int row) const {
  for (size_t i = 0; i < holes.size(); ++i)
    if (holes[i].col == col && holes[i].row == row) return static_cast<int>(i);
  return -1;
}

int TemplateView::seeds_in(int col, int row) const {
  const int i = index(col, row);
  return i >= 0 && i < static_cast<int>(seeds.size()) ? seeds[i] : 0;
}

const frames::PlannedHole* TemplateView::planned(int col, int row) const {
  const int i = frames::find_planned(plan, col, row);
  return i >= 0 ? &plan[i] : nullptr;
}

frames::HoleStatus TemplateView::status(const frames::PlannedHole& p) const {
  return frames::hole_status(seeds_in(p.col, p.row), static_cast<int>(p.seeds_mm.size()));
}

}  // namespace ps::gui
