// Maps a Device to instrument commands, polled once per physics tick (a CommandSource): the
// device's z travel (times `scale`) is the active needle's depth along its path, sent as a
// NeedleAim each tick it changes (with the speed of the change, so the command is smooth within
// the tick); rotation z turns the hub; button presses fire the gun, deposit a seed or select the
// next needle (on the press, not while held); the clutch freezes the mapping while held.
// A device that disconnects mid-session: the needle is held where its command is (a zero-speed
// advance, applied once), the source stops sending, and disconnected()/status() say so; the app
// shows it. Reconnecting resumes from the needle's current depth (no jump).
#pragma once
#include <atomic>
#include <string>
#include <vector>

#include "engine/realtime/tick_runner.h"
#include "engine/sim/scene.h"
#include "haptics/device.h"

namespace ps::haptics {

class DeviceSource final : public CommandSource {
 public:
  // `scene` gives the needle paths and tool indices; the device must outlive the source.
  DeviceSource(const Scene& scene, Device& device, double scale = 1.0);
  void poll(int64_t tick, const Simulation& sim, CommandApplier& apply) override;
  void rewind() override;

  bool disconnected() const { return disconnected_.load(std::memory_order_acquire); }
  // "ok" / "disconnected at t=... s: needle held at ... mm" (any thread; copied)
  std::string status() const;
  int active_needle() const { return needle_; }
  double commanded_depth() const { return depth_; }   // [m]

 private:
  const Scene& scene_;
  Device& dev_;
  double scale_;
  int needle_ = 0;
  bool have_ref_ = false;
  double ref_z_ = 0.0;             // device z at the reference [m]
  double ref_depth_ = 0.0;         // needle depth at the reference [m]
  double depth_ = 0.0;             // last commanded depth of the active needle [m]
  std::vector<double> depth_of_;   // [needles] last commanded depth of each [m]
  double roll_ = 0.0;
  uint32_t buttons_ = 0;
  std::atomic<bool> disconnected_{false};
  std::atomic<double> disconnect_time_{0.0}, disconnect_depth_{0.0};
};

}  // namespace ps::haptics
