// Needles carried by the probe (issue 5 item 3): in biopsy the needle runs in a guide clamped on
// the probe at the clinical angle, in brachytherapy in a hole of the template fixed to the probe's
// stepper. These put a needle of the NeedleTool (engine/tools/needle/needle.h) on that path at the probe's
// current pose, `depth` beyond where it leaves the guide or template, moving along it at `speed`
// (its interactive command: NeedleTool::command). Call them between ticks, after every probe
// command or tick, so the needle follows the probe as it moves (at tick rate: during a tick the
// needle keeps the pose given before it). The needle's coupling spring then drags its tip to the
// commanded point against the tissue's resistance; the path itself is exact.
#pragma once
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"

namespace ps {

struct ScenarioSpec;

// A needle in the probe's biopsy guide (NeedleSpec::guide) starts on the guide at the probe's
// start pose: its start and direction are set from the scenario's probe. Without a probe, or a
// probe without a needle_guide, InputError naming the needle's `guide` line.
void place_guided_needles(ScenarioSpec& spec);

// Point `depth` [m] along a path, and the needle command that holds needle `i` there with
// velocity speed [m/s] along the path.
void hold_needle_on_path(NeedleTool& needles, int i, const NeedlePath& path, double depth, double speed = 0.0);

// The probe's biopsy guide (ProbeTool::biopsy_guide()).
void hold_needle_in_biopsy_guide(NeedleTool& needles, int i, const ProbeTool& probe, double depth, double speed = 0.0);

// Template hole (col, row) (ProbeTool::template_hole(); InputError for a hole off the grid).
void hold_needle_in_template_hole(NeedleTool& needles, int i, const ProbeTool& probe, int col, int row, double depth,
                                  double speed = 0.0);

}  // namespace ps
