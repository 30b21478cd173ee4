// Pictures of a session for its report (report.png, app/session/session_report.h): the 3D view at the end
// (render/, headless EGL or OSMesa) with each needle's target (red) and where its sample went
// (blue), the needles and seeds as their tool draws them; and the simulated TRUS image
// (engine/ultrasound/) at each puncture of the gland, from the state captured at that tick.
// Without headless GL the 3D view is replaced by a note; the report is still written.
#pragma once
#include <string>
#include <vector>

#include "app/session/report_chart.h"
#include "engine/contract/snapshot.h"
#include "engine/metrics/session_metrics.h"
#include "engine/sim/scene.h"
#include "engine/ultrasound/scene.h"

namespace ps::app {

struct PunctureShot {
  double time = 0.0, depth = 0.0, force = 0.0;  // [s], [m], [N]
  std::string needle, organ;
  RgbImage us;                     // grayscale as RGB; empty when no probe
};

struct ReportViews {
  RgbImage view3d;                 // empty: see note3d
  std::string note3d;
  std::vector<PunctureShot> punctures;
  std::string note_us;             // why there is no ultrasound image ("" when there are some)
};

// Positions and instrument geometry of the simulation now, into `out` (x sized once: no
// allocation after the first call for the same scene; the draw lists keep their capacity).
void snapshot_of(const Simulation& sim, Snapshot& out);

// The 3D view of `snap` with the report's markers (targets, samples), w x h pixels.
// On no headless GL: an empty image and the reason in `note`.
RgbImage render_3d_view(const Scene& scene, const Snapshot& snap, const SessionReport& r, int w, int h, std::string& note);

// The TRUS image of `snap` seen from `probe` (transverse when the needle runs along the probe
// axis, as in brachytherapy; else sagittal), size x size pixels.
RgbImage render_us(const Scene& scene, const Snapshot& snap, const us::ProbeView& probe, const Vec3& needle_dir, int size);

}  // namespace ps::app
