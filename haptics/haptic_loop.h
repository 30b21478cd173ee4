// The haptic force loop. The device side runs at 1 kHz even when the tissue ticks slower: each
// physics tick refreshes a local model of the needle-tissue contact along the needle axis,
//   F_tissue(q) = f + K (q - q0)       (f, q0: the tick's axial force and depth; K >= 0 from the
//                                      force change between ticks, bounded by max_contact_stiffness)
// and at 1 kHz the device is coupled to a massless proxy of the needle in that model by a virtual
// coupling (spring k_c + damper b_c): the proxy sits where the coupling spring balances the local
// tissue force, q_p = (k_c u + K q0 - f) / (k_c + K), and the device feels
//   F = -k_c (u - q_p) - b_c u'     clamped to |F| <= max_force.
// The physics side commands the needle to the device's position u each tick (its own
// spring-damper coupling moves it), so tool and device stay coupled both ways.
// Passivity: a model that jumps at each physics tick can inject energy. A passivity observer
// sums the energy the rendering gave the device (sum F u' dt, u' from successive device
// positions as an encoder gives them); when it turns positive, a passivity controller adds just
// the damping that takes it back to zero (Hannaford and Ryu 2002). stats() says how often it
// acted and how much it absorbed.
// Threads: HapticCoupler is the physics side (a CommandSource) and HapticRenderer::step the 1 kHz
// side; they exchange the local model and the device position lock-free (a triple buffer and an
// atomic). run_haptic_lockstep() drives both in lock-step (tests, benchmarks: no wall clock);
// HapticThread runs the renderer on its own thread at 1 kHz against a real device.
#pragma once
#include <atomic>
#include <cstdint>
#include <thread>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/tick_runner.h"
#include "engine/realtime/triple_buffer.h"
#include "engine/sim/scene.h"
#include "haptics/device.h"

namespace ps::haptics {

struct HapticParams {
  double rate_hz = 1000.0;                 // device loop [Hz]
  double coupling_stiffness = 800.0;       // k_c [N/m]
  double coupling_damping = 2.0;           // b_c [N s/m]
  double max_force = 8.0;                  // clamp [N]
  double max_contact_stiffness = 3000.0;   // bound of K [N/m]
  bool passivity_controller = true;
};

struct LocalContact {
  double q0 = 0.0;                 // needle depth along its path at the tick [m]
  double f = 0.0;                  // axial tissue force resisting insertion at the tick [N]
  double k = 0.0;                  // local stiffness dF/dq >= 0 [N/m]
  int64_t tick = -1;
};

struct HapticStats {
  int64_t steps = 0;
  int64_t clamped = 0;             // steps at the force clamp
  int64_t pc_steps = 0;            // steps where the passivity controller acted
  double pc_absorbed = 0.0;        // energy it removed [J]
  double raw_energy_max = 0.0;     // largest energy the rendering alone had given the device [J]
  double max_force = 0.0;          // largest |F| rendered [N]
};

class HapticRenderer {
 public:
  explicit HapticRenderer(HapticParams p = {}) : p_(p) {}
  // Device side: one step at device position u [m] (time step dt); returns the force to render.
  double step(double u, double dt);
  // Physics side: publishes the model of the last tick.
  void publish(const LocalContact& c) {
    models_.back() = c;
    models_.publish();
  }
  const HapticStats& stats() const { return stats_; }
  const HapticParams& params() const { return p_; }
  double proxy() const { return q_p_; }

 private:
  HapticParams p_;
  TripleBuffer<LocalContact> models_;
  HapticStats stats_;
  double u_prev_ = 0.0;
  bool first_ = true;
  double q_p_ = 0.0;
  double w_obs_ = 0.0;             // observed energy given to the device [J]
  double w_raw_ = 0.0;             // same without the controller's correction [J]
};

// Physics side: commands needle `needle` of the scene to the device position each tick and
// refreshes the renderer's local model from the needle's read-out after the tick.
class HapticCoupler final : public CommandSource {
 public:
  HapticCoupler(const Scene& scene, HapticRenderer& r, int needle = 0);
  void set_device_position(double u) { u_.store(u, std::memory_order_release); }   // device side
  void poll(int64_t tick, const Simulation& sim, CommandApplier& apply) override;
  void after_tick(int64_t tick, const Simulation& sim) override;
  void rewind() override;

 private:
  const Scene& scene_;
  HapticRenderer& r_;
  int needle_;
  std::atomic<double> u_{0.0};
  double last_u_ = -1e300;
  bool have_prev_ = false;
  double q_prev_ = 0.0, f_prev_ = 0.0, k_ = 0.0;
};

// Lock-step: for each physics tick, the coupler commands and the physics ticks, then the device
// side runs rate_hz * dt steps with `hand` (a SimulatedHand). Returns false on a fault.
class SimulatedHand;
bool run_haptic_lockstep(LockstepRunner& run, HapticCoupler& coupler, HapticRenderer& r, SimulatedHand& hand, double duration);

// The device side on its own thread at rate_hz against a real device (wall clock).
class HapticThread {
 public:
  HapticThread(Device& dev, HapticRenderer& r, HapticCoupler& c) : dev_(dev), r_(r), c_(c) {}
  ~HapticThread() { stop(); }
  void start();
  void stop();

 private:
  Device& dev_;
  HapticRenderer& r_;
  HapticCoupler& c_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ps::haptics
