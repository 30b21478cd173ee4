#include "haptics/device_source.h"
#include "engine/tools/needle/needle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ps::haptics {

DeviceSource::DeviceSource(const Scene& scene, Device& device, double scale)
    : scene_(scene), dev_(device), scale_(scale), depth_of_(scene.spec.needles.needles.size(), 0.0) {}

void DeviceSource::rewind() {
  needle_ = 0;
  have_ref_ = false;
  depth_ = 0.0;
  std::fill(depth_of_.begin(), depth_of_.end(), 0.0);
  roll_ = 0.0;
  buttons_ = 0;
  disconnected_.store(false);
}

std::string DeviceSource::status() const {
  if (!disconnected()) return std::string(dev_.name()) + ": ok";
  char b[160];
  std::snprintf(b, sizeof b, "%s disconnected at t=%.3f s: the instruments are held where they were (needle at %.1f mm)", dev_.name(),
                disconnect_time_.load(), disconnect_depth_.load() * 1e3);
  return b;
}

void DeviceSource::poll(int64_t tick, const Simulation& sim, CommandApplier& apply) {
  if (!scene_.tools.has<NeedleTool>()) return;
  const auto& needles = scene_.spec.needles.needles;
  if (needles.empty()) return;
  DeviceState st;
  const double t = sim.state().time;
  const bool ok = dev_.poll(t, st) && st.connected;
  Command c;
  c.tick = tick;
  c.tool = static_cast<int16_t>(scene_.tools.index<NeedleTool>());
  c.item = static_cast<int16_t>(needle_);
  if (!ok) {
    if (!disconnected()) {  // once: hold the needle where its command is now
      c.kind = CommandKind::NeedleAdvance;
      c.needle.speed = 0.0;
      apply.apply(c, tick);
      disconnect_time_.store(t);
      disconnect_depth_.store(depth_);
      disconnected_.store(true, std::memory_order_release);
      have_ref_ = false;
    }
    return;
  }
  if (disconnected()) disconnected_.store(false, std::memory_order_release);  // back: resume without a jump
  const uint32_t pressed = st.buttons & ~buttons_;
  buttons_ = st.buttons;
  if (pressed & kButtonNext) {
    depth_of_[needle_] = depth_;
    needle_ = (needle_ + 1) % static_cast<int>(needles.size());
    depth_ = depth_of_[needle_];
    have_ref_ = false;
    c.item = static_cast<int16_t>(needle_);
    c.kind = CommandKind::SelectNeedle;
    apply.apply(c, tick);
  }
  if (!have_ref_ || (st.buttons & kButtonClutch)) {  // (re)reference: no jump
    ref_z_ = st.position.z();
    ref_depth_ = depth_;
    have_ref_ = true;
  }
  const double depth = ref_depth_ + scale_ * (st.position.z() - ref_z_);
  const double dt = sim.model().dt;
  if (depth != depth_ || tick == 0) {
    const NeedleSpec& ns = needles[needle_];
    const Vec3 dir = ns.direction.normalized();
    const Vec3 tip = ns.start + depth * dir;
    c.kind = CommandKind::NeedleAim;
    for (int i = 0; i < 3; ++i) {
      c.needle.pos[i] = tip[i];
      c.needle.dir[i] = dir[i];
    }
    c.needle.speed = 0.0;  // held at the device's pose; the next tick moves it again
    apply.apply(c, tick);
    depth_ = depth;
  }
  (void)dt;
  if (st.rotation.z() != roll_) {
    roll_ = st.rotation.z();
    c.kind = CommandKind::NeedleRotate;
    c.needle.angle = roll_;
    apply.apply(c, tick);
  }
  if (pressed & kButtonFire) {
    c.kind = CommandKind::FireGun;
    apply.apply(c, tick);
  }
  if (pressed & kButtonSeed) {
    c.kind = CommandKind::DepositSeed;
    apply.apply(c, tick);
  }
}

}  // namespace ps::haptics
