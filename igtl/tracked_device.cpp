#include "igtl/tracked_device.h"

#include <Eigen/Geometry>

namespace ps::igtl {

void TrackedDevice::set_pose(const Mat3& r, const Vec3& p) {
  // the nearest rotation (a tracker's matrix may carry scale or rounding)
  Eigen::JacobiSVD<Mat3> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 rot = svd.matrixU() * svd.matrixV().transpose();
  if (rot.determinant() < 0) return;  // a reflection is no pose
  std::lock_guard<std::mutex> lk(mu_);
  if (!have_ref_) {
    r0_ = rot;
    p0_ = p;
    have_ref_ = true;
  }
  latest_.position = r0_.transpose() * (p - p0_);
  const Eigen::AngleAxisd aa(r0_.transpose() * rot);
  latest_.rotation = aa.angle() * aa.axis();
  latest_.connected = true;
  ++received_;
}

int TrackedDevice::poses_received() const {
  std::lock_guard<std::mutex> lk(mu_);
  return received_;
}

bool TrackedDevice::poll(double, haptics::DeviceState& out) {
  std::unique_lock<std::mutex> lk(mu_, std::try_to_lock);
  if (lk.owns_lock()) polled_ = latest_;
  out = polled_;
  return true;
}

}  // namespace ps::igtl
