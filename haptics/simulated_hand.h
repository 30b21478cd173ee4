// A simulated haptic device: a hand modelled as a mass-spring-damper that follows a target
// trajectory (a script's needle depth, or any function of time) while the force rendered on the
// device pushes back. It lets the force loop, the coupling and passivity be tested headless.
//   m x'' = k (x_target - x) + b (v_target - x') + F_rendered
// integrated with semi-implicit Euler at the haptic rate. Position along the instrument [m].
#pragma once
#include <functional>

#include "haptics/device.h"

namespace ps::haptics {

struct HandParams {
  double mass = 0.5;               // hand + handle [kg]
  double stiffness = 300.0;        // arm "muscle" spring to the target [N/m]
  double damping = 25.0;           // [N s/m] (about critical for 0.5 kg, 300 N/m)
};

class SimulatedHand final : public Device {
 public:
  using Target = std::function<double(double)>;   // target position at time t [m]
  SimulatedHand(Target target, HandParams p = {}) : target_(std::move(target)), p_(p) {}
  const char* name() const override { return "simulated hand"; }
  bool poll(double time, DeviceState& out) override;
  void set_force(const Vec3& f) override { force_ = f.z(); }

  // Advances the hand by dt [s] to time t + dt under the last set_force().
  void step(double t, double dt);
  double position() const { return x_; }   // [m]
  double velocity() const { return v_; }   // [m/s]
  double force() const { return force_; }  // rendered force on the hand [N]
  // Work done on the hand by the rendered force since the start [J] (trapezoid on the hand's
  // own velocity): > 0 means the simulation gave the hand energy.
  double work_in() const { return work_; }

 private:
  Target target_;
  HandParams p_;
  double x_ = 0.0, v_ = 0.0, force_ = 0.0, work_ = 0.0;
};

}  // namespace ps::haptics
