// The trainee window's live metrics (issue 13): per needle, the distance from its tip to its
// target carried by the tissue (engine/metrics/tracked_point.h), the peak axial force, punctures
// and structures hit, and the class scale of Han et al. 2012 (freehand 9.0 mm, robot 1.0 mm).
// Computed on the UI thread from the snapshots the window already reads (no access to the
// physics state); the final figures are those of metrics.json (`run --report`), which are taken
// at each needle's decisive moment (core, deepest point), not live.
#pragma once
#include "app/gui/session.h"

namespace ps::gui {

// Draws the panel's widgets for the session's newest snapshot (call after Session::latest()).
void metrics_panel(Session& s, const Snapshot& snap);

}  // namespace ps::gui
