#include "haptics/probe_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/tools/probe/probe.h"

namespace ps::haptics {

namespace {
constexpr double kSpeedMargin = 0.95;            // of the probe's speed limits
constexpr double kTiltLimit = kProbeMaxTiltRad * 0.999;

double lin_dist(const ProbePose& a, const ProbePose& b) { return std::abs(b.insertion - a.insertion) + (b.offset - a.offset).norm(); }
double ang_dist(const ProbePose& a, const ProbePose& b) {
  return std::abs(b.roll - a.roll) + std::abs(b.tilt - a.tilt) + std::abs(b.yaw - a.yaw);
}
bool same(const ProbePose& a, const ProbePose& b) {
  return a.insertion == b.insertion && a.offset == b.offset && a.roll == b.roll && a.tilt == b.tilt && a.yaw == b.yaw;
}
}  // namespace

ProbeSource::ProbeSource(const Scene& scene, Device& device, double scale, double angle_scale)
    : scene_(scene), dev_(device), scale_(scale), angle_scale_(angle_scale) {
  if (scene.spec.probe) {
    const ProbeSpec& ps = *scene.spec.probe;
    const Vec3 a = ps.axis.normalized();
    anterior_ = (ps.anterior - ps.anterior.dot(a) * a).normalized();
    lateral_ = a.cross(anterior_);
    cmd_ = ps.pose;
  }
}

void ProbeSource::rewind() {
  have_ref_ = false;
  sent_ = 0;
  if (scene_.spec.probe) cmd_ = scene_.spec.probe->pose;
  disconnected_.store(false);
}

std::string ProbeSource::status() const {
  if (!disconnected()) return std::string(dev_.name()) + " (probe): ok";
  char b[200];
  std::snprintf(b, sizeof b, "%s (probe) disconnected at t=%.3f s: the probe is held where it was", dev_.name(), disconnect_time_.load());
  return b;
}

void ProbeSource::poll(int64_t tick, const Simulation& sim, CommandApplier& apply) {
  if (!scene_.tools.has<ProbeTool>() || !scene_.spec.probe) return;
  DeviceState st;
  const double t = sim.state().time;
  if (!(dev_.poll(t, st) && st.connected)) {
    if (!disconnected()) {  // the probe finishes its one-tick move and stays there
      disconnect_time_.store(t);
      disconnected_.store(true, std::memory_order_release);
      have_ref_ = false;
    }
    return;
  }
  if (disconnected()) disconnected_.store(false, std::memory_order_release);  // back: re-reference, no jump
  const auto* probe = scene_.tools.as<ProbeTool>();
  if (!have_ref_ || (st.buttons & kButtonClutch)) {
    ref_dev_ = st;
    ref_pose_ = probe ? probe->pose() : cmd_;
    cmd_ = ref_pose_;
    have_ref_ = true;
    return;
  }
  // where the device says the probe should be
  const Vec3 dp = scale_ * (st.position - ref_dev_.position);
  const Vec3 dr = angle_scale_ * (st.rotation - ref_dev_.rotation);
  ProbePose want = ref_pose_;
  want.insertion += dp.z();
  want.offset += dp.x() * lateral_ + dp.y() * anterior_;
  want.tilt = std::clamp(want.tilt + dr.x(), -kTiltLimit, kTiltLimit);
  want.yaw = std::clamp(want.yaw + dr.y(), -kTiltLimit, kTiltLimit);
  want.roll += dr.z();
  if (!(std::isfinite(want.insertion) && want.offset.allFinite() && std::isfinite(want.roll) && std::isfinite(want.tilt) &&
        std::isfinite(want.yaw)))
    return;  // a broken reading moves nothing
  // one tick's worth of motion within the probe's speed limits (the probe's smoothstep peaks at
  // 1.5 x the mean speed, probe.cpp min_duration)
  const ProbeSpec& spec = *scene_.spec.probe;
  const double dt = sim.model().dt;
  const double lin = lin_dist(cmd_, want), ang = ang_dist(cmd_, want);
  double f = 1.0;
  if (lin > 0) f = std::min(f, kSpeedMargin * spec.max_speed * dt / 1.5 / lin);
  if (ang > 0) f = std::min(f, kSpeedMargin * spec.max_angular_speed * dt / 1.5 / ang);
  ProbePose next = cmd_;
  next.insertion += f * (want.insertion - cmd_.insertion);
  next.offset += f * (want.offset - cmd_.offset);
  next.roll += f * (want.roll - cmd_.roll);
  next.tilt += f * (want.tilt - cmd_.tilt);
  next.yaw += f * (want.yaw - cmd_.yaw);
  if (same(next, cmd_)) return;
  Command c;
  c.kind = CommandKind::ProbeMove;
  c.tick = tick;
  c.tool = static_cast<int16_t>(scene_.tools.index<ProbeTool>());
  c.probe.insertion = next.insertion;
  for (int i = 0; i < 3; ++i) c.probe.offset[i] = next.offset[i];
  c.probe.roll = next.roll;
  c.probe.tilt = next.tilt;
  c.probe.yaw = next.yaw;
  c.probe.duration = dt;
  if (apply.apply(c, tick)) {
    cmd_ = next;
    ++sent_;
  }
}

}  // namespace ps::haptics
