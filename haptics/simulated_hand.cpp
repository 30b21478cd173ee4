#include "haptics/simulated_hand.h"

namespace ps::haptics {

bool SimulatedHand::poll(double, DeviceState& out) {
  out.position = Vec3(0, 0, x_);
  out.rotation = Vec3::Zero();
  out.buttons = 0;
  out.connected = true;
  return true;
}

void SimulatedHand::step(double t, double dt) {
  const double xt = target_(t + dt);
  const double vt = (target_(t + dt) - target_(t)) / dt;
  const double a = (p_.stiffness * (xt - x_) + p_.damping * (vt - v_) + force_) / p_.mass;
  const double v0 = v_;
  v_ += a * dt;
  x_ += v_ * dt;
  work_ += force_ * 0.5 * (v0 + v_) * dt;
}

}  // namespace ps::haptics
