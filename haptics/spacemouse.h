// 3Dconnexion SpaceMouse through libspnav (Debian libspnav-dev), used when the spacenavd daemon
// runs. The puck is a velocity device: each of its six axes, deflection times `speed` (x, y, z)
// or `angular_speed` (rx, ry, rz), integrates into the pose it reports. A DeviceSource (needle)
// maps z (+ advances) and rz (hub); a ProbeSource (haptics/probe_source.h) maps all six.
// Button 0 fires, button 1 deposits a seed.
// open() fails with a clear message when spacenavd is not running (the app then falls back to
// mouse and keyboard); a daemon that goes away mid-session reads as a disconnect.
#pragma once
#include <string>

#include "haptics/device.h"

namespace ps::haptics {

class SpaceMouseDevice final : public Device {
 public:
  explicit SpaceMouseDevice(double speed = 0.02, double angular_speed = 1.0) : speed_(speed), angular_speed_(angular_speed) {}
  ~SpaceMouseDevice() override;
  const char* name() const override { return "SpaceMouse"; }
  // Connects to spacenavd. False with `why` set ("spacenavd is not running ...") when it cannot.
  bool open(std::string& why);
  bool poll(double time, DeviceState& out) override;

 private:
  double speed_;                   // [m/s] at full deflection
  double angular_speed_;           // [rad/s] at full deflection
  bool open_ = false;
  double last_time_ = -1.0;
  double axis_[6] = {0, 0, 0, 0, 0, 0};  // last deflection x y z rx ry rz, -1..1
  DeviceState state_;
};

}  // namespace ps::haptics
