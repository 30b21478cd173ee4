#include "engine/tools/probe/probe_geometry.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/util/error.h"

namespace ps {

RectalFrame rectal_frame(const ProbeSpec& spec) {
  RectalFrame f;
  f.entry = spec.entry;
  f.axial = spec.axis.normalized();
  const Vec3 n = spec.anterior - spec.anterior.dot(f.axial) * f.axial;
  if (!(n.norm() > 1e-9)) throw std::invalid_argument("probe anterior direction is parallel to the rectal axis");
  f.anterior = n.normalized();
  f.lateral = f.axial.cross(f.anterior);
  return f;
}

namespace {
Mat3 pose_rotation(const RectalFrame& rf, double tilt, double yaw, double roll) {
  using AA = Eigen::AngleAxisd;
  return (AA(tilt, rf.lateral) * AA(yaw, -rf.anterior) * AA(roll, rf.axial)).toRotationMatrix();
}
Mat3 frame_columns(const RectalFrame& rf) {
  Mat3 F;
  F.col(0) = rf.axial;
  F.col(1) = rf.anterior;
  F.col(2) = rf.lateral;
  return F;
}
Vec3 pivot_of(const RectalFrame& rf, const ProbePose& pose) {
  return rf.entry + pose.offset - pose.offset.dot(rf.axial) * rf.axial;  // offset is transverse
}
}  // namespace

ProbeFrame probe_frame(const ProbeSpec& spec, const RectalFrame& rf, const ProbePose& pose) {
  ProbeFrame f;
  f.pivot = pivot_of(rf, pose);
  f.rot = pose_rotation(rf, pose.tilt, pose.yaw, pose.roll) * frame_columns(rf);
  const Vec3 d = f.rot.col(0);
  f.capsule.tip = f.pivot + pose.insertion * d;
  f.capsule.back = f.capsule.tip - spec.length * d;
  f.capsule.dir = d;
  f.capsule.length = spec.length;
  f.capsule.radius = spec.radius;
  return f;
}

NeedlePath biopsy_guide_path(const ProbeSpec& spec, const ProbeFrame& f) {
  const Vec3 d = f.axis(), n = f.anterior();
  NeedlePath p;
  p.entry = f.capsule.tip - spec.guide_back * d + spec.radius * n;
  p.direction = (std::cos(spec.guide_angle) * d + std::sin(spec.guide_angle) * n).normalized();
  return p;
}

NeedlePath template_hole_path(const ProbeSpec& spec, const RectalFrame& rf, const ProbePose& pose, int col, int row) {
  if (col < 0 || col >= spec.template_cols || row < 0 || row >= spec.template_rows)
    throw InputError("", 0, "template hole",
                     "hole (" + std::to_string(col) + ", " + std::to_string(row) + ") is outside the " +
                         std::to_string(spec.template_cols) + " x " + std::to_string(spec.template_rows) + " template");
  // the stepper carries offset, tilt and yaw; not insertion nor roll
  const Mat3 rot = pose_rotation(rf, pose.tilt, pose.yaw, 0.0) * frame_columns(rf);
  const Vec3 d = rot.col(0), n = rot.col(1), l = rot.col(2);
  const Vec3 centre = pivot_of(rf, pose) - spec.template_distance * d;
  const double x = (col - 0.5 * (spec.template_cols - 1)) * spec.template_pitch;
  const double y = spec.template_first_row + row * spec.template_pitch;
  return NeedlePath{centre + x * l + y * n, d};
}

}  // namespace ps
