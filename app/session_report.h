// The one-page session report picture (report.png) written with metrics.json: force-versus-depth
// of every needle with its punctures, two orthogonal views of the scene at the end (sagittal:
// y-z, coronal: x-z) with each organ's particles, each target where the tissue carried it, the
// needle paths to where they took their sample, and the seeds, and the numbers (score and its
// terms, targeting error against Han et al. 2012, one line per needle).
// The views are 2D projections drawn with app/plot; the shaded 3D view and the ultrasound image
// at each puncture (render/, engine/ultrasound) are not on this branch yet.
#pragma once
#include <vector>

#include "app/report_chart.h"
#include "engine/metrics/score.h"
#include "engine/metrics/session_metrics.h"
#include "engine/tools/needle_output.h"

namespace ps::app {

RgbImage render_session_report(const Model& m, const State& s, const NeedleTool& tool, const ForceDepthRecorder& rec,
                               const SessionReport& report, const Score& score);

}  // namespace ps::app
