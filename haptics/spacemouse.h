// 3Dconnexion SpaceMouse through libspnav (Debian libspnav-dev), used when the spacenavd daemon
// runs. The puck is a velocity device: its z push (+ advances) times `speed` integrates into the
// position the DeviceSource maps; rz turns the hub; button 0 fires, button 1 deposits a seed.
// open() fails with a clear message when spacenavd is not running (the app then falls back to
// mouse and keyboard); a daemon that goes away mid-session reads as a disconnect.
#pragma once
#include <string>

#include "haptics/device.h"

namespace ps::haptics {

class SpaceMouseDevice final : public Device {
 public:
  explicit SpaceMouseDevice(double speed = 0.02) : speed_(speed) {}
  ~SpaceMouseDevice() override;
  const char* name() const override { return "SpaceMouse"; }
  // Connects to spacenavd. False with `why` set ("spacenavd is not running ...") when it cannot.
  bool open(std::string& why);
  bool poll(double time, DeviceState& out) override;

 private:
  double speed_;                   // [m/s] at full deflection
  bool open_ = false;
  double last_time_ = -1.0;
  double axis_z_ = 0.0, axis_rz_ = 0.0;  // last deflection, -1..1
  DeviceState state_;
};

}  // namespace ps::haptics
