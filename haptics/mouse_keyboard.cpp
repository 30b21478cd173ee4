#include "haptics/mouse_keyboard.h"

#include <cmath>

namespace ps::haptics {

void MouseKeyboardDevice::key(Key k, bool down) {
  const uint32_t bit = 1u << k;
  if (down) held_.fetch_or(bit);
  else held_.fetch_and(~bit);
  uint32_t b = 0;
  const uint32_t h = held_.load();
  if (h & (1u << Space)) b |= kButtonFire;
  if (h & (1u << D)) b |= kButtonSeed;
  if (h & (1u << Tab)) b |= kButtonNext;
  if (h & (1u << Shift)) b |= kButtonClutch;
  buttons_.store(b);
  if (down && k == Q) add(roll_, -M_PI / 12);
  if (down && k == E) add(roll_, M_PI / 12);
}

bool MouseKeyboardDevice::poll(double time, DeviceState& out) {
  const double dt = last_time_ < 0 ? 0.0 : time - last_time_;
  last_time_ = time;
  const uint32_t h = held_.load();
  if (h & (1u << W)) key_z_ += key_speed_ * dt;
  if (h & (1u << S)) key_z_ -= key_speed_ * dt;
  if (h & (1u << Up)) key_rx_ += key_rate_ * dt;
  if (h & (1u << Down)) key_rx_ -= key_rate_ * dt;
  if (h & (1u << Right)) key_ry_ += key_rate_ * dt;
  if (h & (1u << Left)) key_ry_ -= key_rate_ * dt;
  out.position = Vec3(0, 0, drag_m_.load() + key_z_);
  out.rotation = Vec3(key_rx_, key_ry_, roll_.load());
  out.buttons = buttons_.load();
  out.connected = connected_.load();
  return out.connected;
}

}  // namespace ps::haptics
