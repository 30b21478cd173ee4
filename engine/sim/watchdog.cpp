#include "engine/sim/watchdog.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ps {

Watchdog::Watchdog(const Model& m, WatchLimits limits) : lim_(limits) {
  if (!(lim_.leave_margin > 0)) lim_.leave_margin = m.leave_margin;
  lo_ = Vec3::Constant(1e300);
  hi_ = Vec3::Constant(-1e300);
  for (int p = 0; p < m.particle_count(); ++p) {
    if (m.inv_mass[p] > 0) total_mass_ += 1.0 / m.inv_mass[p];
    lo_ = lo_.cwiseMin(m.rest_pos[p]);
    hi_ = hi_.cwiseMax(m.rest_pos[p]);
  }
  lo_ -= Vec3::Constant(lim_.leave_margin);
  hi_ += Vec3::Constant(lim_.leave_margin);
}

WatchFinding Watchdog::check(const Model& m, const State& s, WatchPeaks* peaks) const {
  WatchFinding f;
  if (peaks) ++peaks->checks;
  f.time = s.time;
  if (s.fault.kind != StepFault::None) {
    static const char* kinds[] = {"none", "not finite", "too fast", "too far", "volume solve"};
    f.ok = false;
    f.what = std::string("step fault: ") + kinds[s.fault.kind];
    f.particle = s.fault.particle;
    f.value = s.fault.value;
    f.time = s.fault.time;
    return f;
  }
  const int n = m.particle_count();
  int fastest = -1, farthest = -1;
  double vmax2 = 0.0, dmax2 = 0.0, margin = 1e300;
  for (int p = 0; p < n; ++p) {
    const double v2 = s.v[p].squaredNorm();
    if (!std::isfinite(v2) || !s.x[p].allFinite()) {
      f.ok = false;
      f.what = "not finite";
      f.particle = p;
      return f;
    }
    if (v2 > vmax2) { vmax2 = v2; fastest = p; }
    const Vec3& x = s.x[p];
    if ((x.array() < lo_.array()).any() || (x.array() > hi_.array()).any()) {
      f.ok = false;
      f.what = "left the scene";
      f.particle = p;
      f.value = (x - m.rest_pos[p]).norm();
      if (peaks) peaks->min_margin = std::min(peaks->min_margin, 0.0);
      return f;
    }
    if (peaks) {
      margin = std::min(margin, std::min((x - lo_).minCoeff(), (hi_ - x).minCoeff()));
      if (m.inv_mass[p] > 0) {
        const double d2 = (x - m.rest_pos[p]).squaredNorm();
        if (d2 > dmax2) { dmax2 = d2; farthest = p; }
      }
    }
  }
  const double ke = kinetic_energy(m, s);
  if (peaks) {
    const double v = std::sqrt(vmax2), d = std::sqrt(dmax2);
    if (v > peaks->max_speed) { peaks->max_speed = v; peaks->fastest = fastest; peaks->max_speed_time = s.time; }
    if (ke > peaks->max_kinetic) { peaks->max_kinetic = ke; peaks->max_kinetic_time = s.time; }
    if (d > peaks->max_displacement) { peaks->max_displacement = d; peaks->farthest = farthest; }
    peaks->min_margin = std::min(peaks->min_margin, margin);
  }
  if (std::sqrt(vmax2) > lim_.max_speed || ke > 0.5 * total_mass_ * lim_.max_speed * lim_.max_speed) {
    f.ok = false;
    f.what = "energy growth";
    f.particle = fastest;
    f.value = std::sqrt(vmax2);
    return f;
  }
  for (size_t si = 0; si < m.surfaces.size(); ++si) {
    const auto& surf = m.surfaces[si];
    if (!surf.volume_constrained || !(s.target_volume[si] > 0)) continue;
    double vol = 0.0;  // closed-surface volume by the divergence theorem
    for (const auto& t : surf.faces) vol += s.x[t[0]].dot(s.x[t[1]].cross(s.x[t[2]])) / 6.0;
    const double drift = std::abs(vol - s.target_volume[si]) / s.target_volume[si];
    if (peaks && drift > peaks->max_volume_drift) {
      peaks->max_volume_drift = drift;
      peaks->worst_surface = static_cast<int>(si);
      peaks->max_volume_drift_time = s.time;
    }
    if (drift > lim_.volume_drift) {
      f.ok = false;
      f.what = "volume drift";
      f.particle = surf.faces.empty() ? -1 : surf.faces[0][0];
      f.value = drift;
      return f;
    }
  }
  return f;
}

std::string WatchFinding::describe(const Model& m) const {
  if (ok) return "ok";
  char b[320];
  if (particle >= 0 && particle < m.particle_count()) {
    const Vec3 r = m.rest_pos[particle] * 1e3;
    const int c = m.component_of[particle];
    std::snprintf(b, sizeof b, "%s at t=%.6g s, particle %d (%s, rest [%.1f, %.1f, %.1f] mm), value %.3g",
                  what.c_str(), time, particle, c >= 0 ? m.components[c].name.c_str() : "?", r.x(), r.y(), r.z(),
                  value);
  } else {
    std::snprintf(b, sizeof b, "%s at t=%.6g s, value %.3g", what.c_str(), time, value);
  }
  return b;
}

}  // namespace ps
