// A tracked physical instrument (PLUS, an optical or electromagnetic tracker) as an input device
// (haptics/device.h): the OpenIGTLink server hands it every TRANSFORM it receives for that
// instrument; the physics thread polls it through the same sources as the SpaceMouse
// (haptics::ProbeSource for the probe, haptics::DeviceSource for the active needle), which move
// the instrument by the device's motion since their first poll.
// The device reports the tracked tool's motion in the tool's own frame at the first transform
// received (its reference): position = R0^T (p - p0) [m], so z is the travel along the tool's
// z axis (the instrument's insertion direction: the probe or needle axis), x and y across it;
// rotation = the rotation vector of R0^T R (rx tilts toward the tool's y, ry yaws, rz rolls
// about its axis). Before any transform the tool is at its reference (no motion).
// The receiving thread writes under a mutex; the physics thread only try_locks it and keeps the
// previous pose when it is busy (it never waits).
#pragma once
#include <mutex>

#include "engine/util/vec.h"
#include "haptics/device.h"

namespace ps::igtl {

class TrackedDevice final : public haptics::Device {
 public:
  explicit TrackedDevice(const char* name) : name_(name) {}
  const char* name() const override { return name_; }
  bool poll(double time, haptics::DeviceState& out) override;

  // The receiving thread: a tool pose in the tracker's frame, rotation R (columns: the tool's
  // axes) and position p [m].
  void set_pose(const Mat3& r, const Vec3& p);
  int poses_received() const;

 private:
  const char* name_;
  mutable std::mutex mu_;
  bool have_ref_ = false;
  Mat3 r0_ = Mat3::Identity();
  Vec3 p0_ = Vec3::Zero();
  haptics::DeviceState latest_;    // relative to the reference
  int received_ = 0;
  haptics::DeviceState polled_;    // the physics thread's last read
};

}  // namespace ps::igtl
