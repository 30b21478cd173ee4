// Mouse and keyboard as a Device (bindings in docs/realtime.md; the app's window feeds the
// events, the physics thread polls): the UI thread calls the setters, the physics thread polls;
// the shared state is a few atomics (no lock, neither side waits).
//   vertical drag with the left button: needle depth (1 px = px_to_m, up advances)
//   W / S held: advance / retract at key_speed;  Q / E: turn the hub -/+ 15 degrees
//   Space: fire the gun;  D: deposit a seed;  Tab: next needle;  Shift held: clutch
//   arrows held: rotation x (Up / Down) and y (Right / Left) at key_rate (the probe's tilt and yaw
//   when this device drives the probe, haptics/probe_source.h)
#pragma once
#include <atomic>

#include "haptics/device.h"

namespace ps::haptics {

class MouseKeyboardDevice final : public Device {
 public:
  enum Key : int { W, S, Q, E, Space, D, Tab, Shift, Up, Down, Left, Right, kKeys };
  explicit MouseKeyboardDevice(double px_to_m = 1e-4, double key_speed = 0.01, double key_rate = 0.2)
      : px_to_m_(px_to_m), key_speed_(key_speed), key_rate_(key_rate) {}
  const char* name() const override { return "mouse+keyboard"; }

  // --- UI thread ---
  void drag(double dy_px) { add(drag_m_, -dy_px * px_to_m_); }   // screen y grows downwards
  void key(Key k, bool down);
  void set_connected(bool c) { connected_.store(c); }             // window focus lost, etc.

  // --- physics thread ---
  bool poll(double time, DeviceState& out) override;

 private:
  static void add(std::atomic<double>& a, double d) {
    double v = a.load();
    while (!a.compare_exchange_weak(v, v + d)) {
    }
  }
  double px_to_m_, key_speed_;
  double key_rate_;                    // arrow keys [rad/s]
  std::atomic<double> drag_m_{0.0};
  std::atomic<double> roll_{0.0};
  std::atomic<uint32_t> held_{0};      // keys held (bit per Key)
  std::atomic<uint32_t> buttons_{0};   // Button bits held
  std::atomic<bool> connected_{true};
  double last_time_ = -1.0;
  double key_z_ = 0.0;                 // travel from W/S [m]
  double key_rx_ = 0.0, key_ry_ = 0.0; // rotation from the arrows [rad]
};

}  // namespace ps::haptics
