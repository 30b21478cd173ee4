// instruments.csv (`replay --out DIR`): the instruments' poses over a run, one row per frame per
// needle, in the scene frame (mm; `dir` a unit vector; angles in degrees):
//   t_s,needle,tip_x_mm,tip_y_mm,tip_z_mm,dir_x,dir_y,dir_z,depth_mm,probe_x_mm,probe_y_mm,probe_z_mm,
//   probe_roll_deg,probe_tilt_deg,probe_yaw_deg,probe_insertion_mm,probe_force_n
// depth: the tip's depth along the needle's path (a needle in the probe's guide: beyond the guide's
// exit); probe: the centre of its tip hemisphere, its commanded pose and the magnitude of the
// tissue's force on it (tick mean). The probe columns are empty in a scene without a probe.
#pragma once
#include <string>

#include "engine/sim/scene.h"

namespace ps {

class InstrumentsCsv {
 public:
  static const char* header();
  // Appends the rows of this moment (between ticks; allocates).
  void add(const Scene& scene);
  const std::string& text() const { return text_; }
  // header + rows, atomically (engine/util/atomic_file.h)
  void write(const std::string& path) const;

 private:
  std::string text_;
};

}  // namespace ps
