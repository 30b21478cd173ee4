#include "haptics/spacemouse.h"

#include <spnav.h>

#include <algorithm>

namespace ps::haptics {

namespace {
constexpr double kFullScale = 350.0;  // libspnav motion units at full deflection
}

SpaceMouseDevice::~SpaceMouseDevice() {
  if (open_) spnav_close();
}

bool SpaceMouseDevice::open(std::string& why) {
  if (spnav_open() == -1) {
    why = "SpaceMouse: cannot connect to spacenavd (is the daemon running? `sudo systemctl start spacenavd`); "
          "falling back to mouse and keyboard";
    return false;
  }
  open_ = true;
  return true;
}

bool SpaceMouseDevice::poll(double time, DeviceState& out) {
  if (!open_) {
    out = state_;
    out.connected = false;
    return false;
  }
  spnav_event ev;
  int n;
  while ((n = spnav_poll_event(&ev)) > 0) {
    if (ev.type == SPNAV_EVENT_MOTION) {
      const int raw[6] = {ev.motion.x, ev.motion.y, ev.motion.z, ev.motion.rx, ev.motion.ry, ev.motion.rz};
      for (int i = 0; i < 6; ++i) axis_[i] = std::clamp(raw[i] / kFullScale, -1.0, 1.0);
    } else if (ev.type == SPNAV_EVENT_BUTTON) {
      const uint32_t bit = ev.button.bnum == 0 ? kButtonFire : ev.button.bnum == 1 ? kButtonSeed : kButtonNext;
      if (ev.button.press) state_.buttons |= bit;
      else state_.buttons &= ~bit;
    }
  }
  if (n < 0 || spnav_fd() < 0) {  // the daemon went away
    open_ = false;
    state_.connected = false;
    out = state_;
    return false;
  }
  const double dt = last_time_ < 0 ? 0.0 : time - last_time_;
  last_time_ = time;
  for (int i = 0; i < 3; ++i) {
    state_.position[i] += speed_ * axis_[i] * dt;
    state_.rotation[i] += angular_speed_ * axis_[3 + i] * dt;
  }
  state_.connected = true;
  out = state_;
  return true;
}

}  // namespace ps::haptics
