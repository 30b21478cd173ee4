#include "engine/io/instruments_csv.h"

#include <cmath>
#include <cstdio>

#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/util/atomic_file.h"

namespace ps {

namespace {
constexpr double kDeg = 180.0 / 3.14159265358979323846;
}

const char* InstrumentsCsv::header() {
  return "t_s,needle,tip_x_mm,tip_y_mm,tip_z_mm,dir_x,dir_y,dir_z,depth_mm,probe_x_mm,probe_y_mm,probe_z_mm,"
         "probe_roll_deg,probe_tilt_deg,probe_yaw_deg,probe_insertion_mm,probe_force_n\n";
}

void InstrumentsCsv::add(const Scene& scene) {
  const NeedleTool* found = scene.sim ? scene.tools.as<NeedleTool>() : nullptr;
  if (!found) return;
  const NeedleTool& needles = *found;
  const ProbeTool* probe = scene.tools.as<ProbeTool>();
  char probe_cols[200] = ",,,,,,,";
  if (probe) {
    const Vec3 c = probe->frame().capsule.tip * 1e3;
    const ProbePose& p = probe->pose();
    std::snprintf(probe_cols, sizeof probe_cols, "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.5f", c.x(), c.y(), c.z(), p.roll * kDeg,
                  p.tilt * kDeg, p.yaw * kDeg, p.insertion * 1e3, probe->reaction_force().norm());
  }
  const double t = scene.sim->state().time;
  char row[512];
  for (int i = 0; i < needles.count(); ++i) {
    const NeedleReadout& r = needles.readout(i);
    const Vec3 tip = r.tip * 1e3;
    std::snprintf(row, sizeof row, "%.6f,%s,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.4f,%s\n", t, needles.spec(i).name.c_str(), tip.x(),
                  tip.y(), tip.z(), r.direction.x(), r.direction.y(), r.direction.z(), r.plan_depth * 1e3, probe_cols);
    text_ += row;
  }
}

void InstrumentsCsv::write(const std::string& path) const { write_file_atomic(path, std::string(header()) + text_); }

}  // namespace ps
