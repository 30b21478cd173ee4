// Input devices behind one interface: pose and buttons in, force out, polled at the physics rate
// (by a DeviceSource, haptics/device_source.h) or at 1 kHz (by the haptic loop). Implementations:
// mouse + keyboard (mouse_keyboard.h), SpaceMouse through libspnav (spacemouse.h), the simulated
// haptic hand (simulated_hand.h); the scripted device is engine/realtime/script.h.
// Nothing in haptics/ includes GL, GLFW or ImGui.
#pragma once
#include <cstdint>

#include "engine/util/vec.h"

namespace ps::haptics {

enum Button : uint32_t {
  kButtonFire = 1u << 0,      // biopsy gun
  kButtonSeed = 1u << 1,      // deposit a seed
  kButtonNext = 1u << 2,      // select the next needle
  kButtonClutch = 1u << 3,    // held: device motion does not move the instrument (re-centre)
};

struct DeviceState {
  Vec3 position = Vec3::Zero();    // device frame [m]: z = along the instrument (+ advances)
  Vec3 rotation = Vec3::Zero();    // device rotation (rx, ry, rz) [rad]; rz turns the needle hub
  uint32_t buttons = 0;            // Button bits held
  bool connected = true;
};

class Device {
 public:
  virtual ~Device() = default;
  virtual const char* name() const = 0;
  // Reads the device now; returns false (and connected = false) when it is gone.
  virtual bool poll(double time, DeviceState& out) = 0;
  // Force to render on the device [N] (devices without actuators ignore it).
  virtual void set_force(const Vec3& /*force*/) {}
};

}  // namespace ps::haptics
