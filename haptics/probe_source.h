// Maps a Device to the TRUS probe's pose, polled once per physics tick (a CommandSource), the way
// DeviceSource maps one to the active needle. Device axes (device.h) -> probe pose
// (scenario_spec.h ProbePose, in the rectal frame):
//   position z -> insertion along the probe axis (+ deeper)
//   position x -> offset along lateral (axis x anterior),  position y -> offset along anterior
//   rotation x -> tilt (toward anterior), rotation y -> yaw (toward lateral), rotation z -> roll
// each relative to where the device was when the mapping took hold (first poll, or the clutch
// button released), added to the probe's pose then: no jump when it starts. Each tick the
// commanded pose moves toward the device's, limited to 95 % of the probe's own speed limits
// (ProbeSpec max_speed, max_angular_speed: the probe would otherwise lengthen the move and report
// it), tilt and yaw held within +-45 degrees, and is sent as a ProbeMove over one tick when it
// changed. A device that disconnects leaves the probe where it is; disconnected()/status() say so.
// Nothing is allocated per tick.
//
// Mouse and keyboard (haptics/mouse_keyboard.h) give z (vertical drag, W/S), rotation z (Q/E) and
// rotation x / y (arrow keys): insertion, roll, tilt, yaw. The SpaceMouse gives all six axes.
#pragma once
#include <atomic>
#include <string>

#include "engine/realtime/tick_runner.h"
#include "engine/sim/scene.h"
#include "haptics/device.h"

namespace ps::haptics {

class ProbeSource final : public CommandSource {
 public:
  // `scene` must have a probe (scene.tools.has<ProbeTool>(); otherwise the source does nothing).
  // scale: probe metres per device metre; angle_scale: probe radians per device radian.
  ProbeSource(const Scene& scene, Device& device, double scale = 1.0, double angle_scale = 1.0);
  void poll(int64_t tick, const Simulation& sim, CommandApplier& apply) override;
  void rewind() override;

  bool disconnected() const { return disconnected_.load(std::memory_order_acquire); }
  std::string status() const;                       // any thread
  const ProbePose& commanded() const { return cmd_; }  // physics thread (or when stopped)
  int64_t commands_sent() const { return sent_; }

 private:
  const Scene& scene_;
  Device& dev_;
  double scale_, angle_scale_;
  Vec3 lateral_ = Vec3::UnitX(), anterior_ = Vec3::UnitY();  // rectal frame (unit)
  bool have_ref_ = false;
  DeviceState ref_dev_;            // device at the reference
  ProbePose ref_pose_;             // probe pose at the reference
  ProbePose cmd_;                  // last commanded pose
  int64_t sent_ = 0;
  std::atomic<bool> disconnected_{false};
  std::atomic<double> disconnect_time_{0.0};
};

}  // namespace ps::haptics
