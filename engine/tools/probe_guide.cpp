#include "engine/tools/probe_guide.h"

namespace ps {

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
