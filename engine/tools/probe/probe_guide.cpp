#include "engine/tools/probe/probe_guide.h"

#include "engine/spec/scenario_spec.h"
#include "engine/util/error.h"

namespace ps {

void place_guided_needles(ScenarioSpec& spec) {
  for (NeedleSpec& n : spec.needles.needles) {
    if (n.guide.empty()) continue;
    if (!spec.probe)
      throw InputError(n.file, n.line, n.key + ".guide",
                       "needle '" + n.name + "' rides in the probe's biopsy guide, but the scene has no probe");
    if (!spec.probe->has_guide)
      throw InputError(n.file, n.line, n.key + ".guide",
                       "needle '" + n.name + "' rides in the probe's biopsy guide, but the probe has no needle_guide");
    const ProbeSpec& ps = *spec.probe;
    const NeedlePath g = biopsy_guide_path(ps, probe_frame(ps, rectal_frame(ps), ps.pose));
    n.start = g.entry;
    n.direction = g.direction;
  }
}

void hold_needle_on_path(NeedleTool& needles, int i, const NeedlePath& path, double depth, double speed) {
  needles.command(i, path.entry + depth * path.direction, path.direction, speed * path.direction);
}

void hold_needle_in_biopsy_guide(NeedleTool& needles, int i, const ProbeTool& probe, double depth, double speed) {
  hold_needle_on_path(needles, i, probe.biopsy_guide(), depth, speed);
}

void hold_needle_in_template_hole(NeedleTool& needles, int i, const ProbeTool& probe, int col, int row, double depth,
                                  double speed) {
  hold_needle_on_path(needles, i, probe.template_hole(col, row), depth, speed);
}

}  // namespace ps
