// The one-page session report picture (report.png) written with metrics.json: force-versus-depth
// of every needle with its punctures, two orthogonal views of the scene at the end (sagittal:
// y-z, coronal: x-z) with each organ's particles, each target where the tissue carried it, the
// needle paths to where they took their sample, and the seeds, and the numbers (score and its
// terms, targeting error against Han et al. 2012, one line per needle).
// With `views` (run / replay --report, app/session/session_views.h) the page has three columns:
//   force versus depth | 3D view at the end (render/)       | sagittal projection
//   the numbers        | ultrasound at each gland puncture   | coronal projection
// without (insert), two: force | sagittal / numbers | coronal.
#pragma once
#include <vector>

#include "app/session/report_chart.h"
#include "app/session/session_views.h"
#include "engine/metrics/score.h"
#include "engine/metrics/session_metrics.h"
#include "engine/tools/needle/needle_output.h"

namespace ps::app {

RgbImage render_session_report(const Model& m, const State& s, const NeedleTool& tool, const ForceDepthRecorder& rec,
                               const SessionReport& report, const Score& score, const ReportViews* views = nullptr);

}  // namespace ps::app
