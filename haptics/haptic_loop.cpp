#include "haptics/haptic_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "haptics/simulated_hand.h"
#include "engine/tools/needle/needle.h"

namespace ps::haptics {

double HapticRenderer::step(double u, double dt) {
  models_.update();
  const LocalContact& m = models_.front();
  const double kc = p_.coupling_stiffness;
  const double v = first_ ? 0.0 : (u - u_prev_) / dt;   // encoder-style velocity
  first_ = false;
  u_prev_ = u;
  // proxy in the local contact model (no contact model yet: the proxy follows the device)
  q_p_ = m.tick < 0 ? u : (kc * u + m.k * m.q0 - m.f) / (kc + m.k);
  double f = -kc * (u - q_p_) - p_.coupling_damping * v;
  if (std::abs(f) > p_.max_force) {
    f = std::copysign(p_.max_force, f);
    ++stats_.clamped;
  }
  // passivity observer / controller on the device port
  w_raw_ += f * v * dt;
  stats_.raw_energy_max = std::max(stats_.raw_energy_max, w_raw_);
  w_obs_ += f * v * dt;
  if (p_.passivity_controller && w_obs_ > 0.0 && v * v * dt > 1e-18) {
    const double alpha = w_obs_ / (v * v * dt);   // damping that removes the excess this step
    f -= alpha * v;
    stats_.pc_absorbed += w_obs_;
    w_obs_ = 0.0;
    ++stats_.pc_steps;
  }
  ++stats_.steps;
  stats_.max_force = std::max(stats_.max_force, std::abs(f));
  return f;
}

HapticCoupler::HapticCoupler(const Scene& scene, HapticRenderer& r, int needle) : scene_(scene), r_(r), needle_(needle) {}

void HapticCoupler::rewind() {
  last_u_ = -1e300;
  have_prev_ = false;
  k_ = 0.0;
}

void HapticCoupler::poll(int64_t tick, const Simulation&, CommandApplier& apply) {
  if (!scene_.tools.has<NeedleTool>()) return;
  const double u = u_.load(std::memory_order_acquire);
  if (u == last_u_) return;
  last_u_ = u;
  const NeedleSpec& ns = scene_.spec.needles.needles.at(needle_);
  const Vec3 dir = ns.direction.normalized();
  const Vec3 tip = ns.start + u * dir;
  Command c;
  c.kind = CommandKind::NeedleAim;
  c.tool = static_cast<int16_t>(scene_.tools.index<NeedleTool>());
  c.item = static_cast<int16_t>(needle_);
  for (int i = 0; i < 3; ++i) {
    c.needle.pos[i] = tip[i];
    c.needle.dir[i] = dir[i];
  }
  apply.apply(c, tick);
}

void HapticCoupler::after_tick(int64_t tick, const Simulation& sim) {
  if (!scene_.tools.has<NeedleTool>()) return;
  ToolReadout ro;
  sim.tools()[scene_.tools.index<NeedleTool>()]->readout(ro, sim.model(), sim.state());
  const double q = ro.value;   // needle: plan depth [m]
  const double f = ro.force;   // axial tissue force, tick mean [N]
  if (have_prev_ && std::abs(q - q_prev_) > 1e-6) {
    const double k = (f - f_prev_) / (q - q_prev_);
    // a stiffness seen while the force rises with depth; relaxes when it does not
    k_ = std::clamp(std::isfinite(k) ? k : 0.0, 0.0, r_.params().max_contact_stiffness);
  }
  if (std::abs(f) < 1e-9) k_ = 0.0;  // out of contact
  have_prev_ = true;
  q_prev_ = q;
  f_prev_ = f;
  r_.publish(LocalContact{q, f, k_, tick});
}

bool run_haptic_lockstep(LockstepRunner& run, HapticCoupler& coupler, HapticRenderer& r, SimulatedHand& hand, double duration) {
  const double dt = run.sim().model().dt;
  const double h = 1.0 / r.params().rate_hz;
  const int per_tick = std::max(1, static_cast<int>(std::lround(dt / h)));
  const double hs = dt / per_tick;
  const int64_t end = static_cast<int64_t>(std::llround(duration / dt));
  double t = run.time();
  while (run.tick() < end) {
    coupler.set_device_position(hand.position());
    if (!run.step()) return false;
    for (int i = 0; i < per_tick; ++i) {
      const double f = r.step(hand.position(), hs);
      hand.set_force(Vec3(0, 0, f));
      hand.step(t, hs);
      t += hs;
    }
  }
  return true;
}

void HapticThread::start() {
  stop_.store(false);
  thread_ = std::thread([this] {
    using Clock = std::chrono::steady_clock;
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / r_.params().rate_hz));
    auto next = Clock::now();
    const auto t0 = next;
    DeviceState st;
    while (!stop_.load(std::memory_order_acquire)) {
      const double t = std::chrono::duration<double>(Clock::now() - t0).count();
      if (dev_.poll(t, st)) {
        c_.set_device_position(st.position.z());
        dev_.set_force(Vec3(0, 0, r_.step(st.position.z(), 1.0 / r_.params().rate_hz)));
      } else {
        dev_.set_force(Vec3::Zero());
      }
      next += period;  // from the schedule, not from now: no drift
      std::this_thread::sleep_until(next);
    }
    dev_.set_force(Vec3::Zero());
  });
}

void HapticThread::stop() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

}  // namespace ps::haptics
