// Needle output written outside the step: per-needle force-vs-depth samples (one per tick,
// taken by the driver after tick()), and CSV files of the samples, the events, the seeds and
// the biopsy cores. Files are written atomically (engine/util/atomic_file.h).
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "engine/tools/needle/needle.h"

namespace ps {

struct ForceDepthSample {
  double time = 0.0;               // [s]
  double depth = 0.0;              // insertion depth since first contact [m]
  double plan_depth = 0.0;         // tip depth along the planned line [m]
  double axial_force = 0.0;        // tissue resistance along the shaft, tick average [N]
  double press_force = 0.0;        // [N] (last substep)
  double cutting_force = 0.0;      // [N]
  double friction_force = 0.0;     // [N]
  Vec3 tip = Vec3::Zero();         // [m]
  int engaged_nodes = 0, stuck_nodes = 0;
  bool contacted = false;
};

// Shape of a force-vs-depth curve (Okamura 2004): the puncture peak, and the mean force over a
// depth window after it (the plateau of cutting + friction).
struct ForceDepthMetrics {
  double peak_force = 0.0;         // largest axial force [N]
  double peak_depth = 0.0;         // depth where it occurs [m]
  double plateau_force = NAN;      // mean axial force for depth in [plateau_lo, plateau_hi] [N]
  int plateau_samples = 0;
  double end_force = 0.0, end_depth = 0.0;  // last sample [N], [m]
};
// Samples before first contact are ignored.
ForceDepthMetrics force_depth_metrics(const std::vector<ForceDepthSample>& samples, double plateau_lo, double plateau_hi);

class ForceDepthRecorder {
 public:
  explicit ForceDepthRecorder(int needles) : samples_(static_cast<size_t>(needles)) {}
  // One sample per needle at the current state (call between ticks).
  void sample(const NeedleTool& tool, double time);
  const std::vector<ForceDepthSample>& samples(int needle) const { return samples_.at(needle); }

 private:
  std::vector<std::vector<ForceDepthSample>> samples_;
};

// header: time_s,depth_mm,plan_depth_mm,axial_force_n,press_n,cutting_n,friction_n,
//         tip_x_mm,tip_y_mm,tip_z_mm,engaged_nodes,stuck_nodes,contacted
std::string force_depth_csv(const std::vector<ForceDepthSample>& samples);
void write_force_depth_csv(const std::string& path, const std::vector<ForceDepthSample>& samples);
// header: time_s,needle,event,component,node,depth_mm,force_n,x_mm,y_mm,z_mm,value
std::string needle_events_csv(const NeedleTool& tool, const Model& model);
// header: needle,seed,deposited,embedded,time_s,planned_x_mm,...,current_z_mm,error_mm
std::string seeds_csv(const NeedleTool& tool);
// header: needle,taken,time_s,component,particles,tumour_particles,tumour_length_mm,notch_length_mm,site
// (site: core_site(core).label, engine/tools/needle/biopsy.h; empty without prostate_zones:)
std::string cores_csv(const NeedleTool& tool);

}  // namespace ps
