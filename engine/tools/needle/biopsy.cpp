// Biopsy gun and core sample (paper Fig. 1, 14). A spring-loaded gun advances the needle by
// `stroke` within `duration` (tens of milliseconds): the commanded depth gets a linear ramp on
// top of the script, and the coupling drives the needle through the tissue at ~1-2 m/s. When
// the stroke has ended and the tissue has had `settle` to close in, the core is what lies in the
// specimen notch: particles whose current position is between notch_offset and notch_offset +
// notch_length behind the tip and within notch_radius of the axis. Reported per component
// (organ) and per particle tag (prostate zone, lesion), and for tumour particles (a tumour
// component or tag) the length of the core they fill: the union along the axis of one particle
// spacing around each tumour particle, clipped to the notch.
#include "engine/tools/needle/biopsy.h"

#include <algorithm>

#include "engine/anatomy/zones.h"
#include "engine/tools/needle/needle_internal.h"

namespace ps {

double gun_stroke(const NeedleTool::Needle& nd, double t) {
  if (!nd.spec.gun || std::isnan(nd.fire_time)) return 0.0;
  const BiopsyGunSpec& g = *nd.spec.gun;
  return g.stroke * std::clamp((t - nd.fire_time) / g.duration, 0.0, 1.0);
}

double gun_stroke_rate(const NeedleTool::Needle& nd, double t) {
  if (!nd.spec.gun || std::isnan(nd.fire_time)) return 0.0;
  const BiopsyGunSpec& g = *nd.spec.gun;
  const double u = (t - nd.fire_time) / g.duration;
  return (u > 0.0 && u < 1.0) ? g.stroke / g.duration : 0.0;
}

void update_biopsy(NeedleTool::Needle& nd, const Model& m, const State& s, NeedleEventRing& events) {
  if (!nd.spec.gun || std::isnan(nd.fire_time) || nd.core.taken) return;
  const BiopsyGunSpec& g = *nd.spec.gun;
  if (s.time < nd.fire_time + g.duration + g.settle) return;
  CoreState& core = nd.core;
  core.taken = true;
  core.time = s.time;
  core.tip = nd.T;
  core.direction = nd.d;
  core.particles.clear();
  core.tumour_pos.clear();
  core.tumour_half.clear();
  std::fill(core.per_component.begin(), core.per_component.end(), 0);
  std::fill(core.per_tag.begin(), core.per_tag.end(), 0);
  const bool tagged = !m.particle_tags.empty();
  core.overflow = 0;
  const double a_hi = -g.notch_offset, a_lo = -(g.notch_offset + g.notch_length);
  const double r2 = nd.notch_radius * nd.notch_radius;
  for (int p : nd.tracked) {
    const Vec3 rel = s.x[p] - nd.T;
    const double a = rel.dot(nd.d);
    if (a < a_lo || a > a_hi || rel.squaredNorm() - a * a > r2) continue;
    const int c = m.component_of[p];
    ++core.per_component[c];
    const uint64_t tags = tagged ? m.particle_tags[p] : 0;
    for (size_t t = 0; t < core.per_tag.size(); ++t)
      if (tags & (uint64_t{1} << t)) ++core.per_tag[t];
    if (static_cast<int>(core.particles.size()) < kCoreCapacity) core.particles.push_back(p);
    else ++core.overflow;
    if ((nd.tumour[c] || (tags & nd.tumour_tags)) && static_cast<int>(core.tumour_pos.size()) < kCoreCapacity) {
      core.tumour_pos.push_back(-a);
      core.tumour_half.push_back(0.5 * m.components[c].spacing);
    }
  }
  // union of [u - h/2, u + h/2] clipped to the notch, sorted by start (insertion sort: small)
  const int nt = static_cast<int>(core.tumour_pos.size());
  core.tumour_particles = nt;
  for (int i = 1; i < nt; ++i)
    for (int j = i; j > 0 && core.tumour_pos[j] - core.tumour_half[j] < core.tumour_pos[j - 1] - core.tumour_half[j - 1]; --j) {
      std::swap(core.tumour_pos[j], core.tumour_pos[j - 1]);
      std::swap(core.tumour_half[j], core.tumour_half[j - 1]);
    }
  double length = 0.0, cur_lo = 0.0, cur_hi = -1.0;
  for (int i = 0; i < nt; ++i) {
    const double lo = std::max(core.tumour_pos[i] - core.tumour_half[i], -a_hi);
    const double hi = std::min(core.tumour_pos[i] + core.tumour_half[i], -a_lo);
    if (hi <= lo) continue;
    if (lo > cur_hi) {
      if (cur_hi > cur_lo) length += cur_hi - cur_lo;
      cur_lo = lo;
      cur_hi = hi;
    } else {
      cur_hi = std::max(cur_hi, hi);
    }
  }
  if (cur_hi > cur_lo) length += cur_hi - cur_lo;
  core.tumour_length = length;
  push_event(events, nd, NeedleEventKind::Core, s.time, nd.T, -1, -1, static_cast<double>(core.particles.size() + core.overflow));
}

CoreSite core_site(const CoreReport& core) {
  using anatomy::kZoneTagNames;
  CoreSite site;
  int count[kZoneTagNames.size()] = {};
  for (const auto& [name, n] : core.per_tag) {
    const auto it = std::find(kZoneTagNames.begin(), kZoneTagNames.end(), name);
    if (it == kZoneTagNames.end()) {
      site.lesions.emplace_back(name, n);
    } else {
      count[it - kZoneTagNames.begin()] += n;
      site.zones.emplace_back(name, n);
    }
  }
  auto most_first = [](const auto& a, const auto& b) { return a.second > b.second; };
  std::stable_sort(site.zones.begin(), site.zones.end(), most_first);
  std::stable_sort(site.lesions.begin(), site.lesions.end(), most_first);
  // the groups of kZoneTagNames: level [0, 3), side [3, 5), medial/lateral [5, 7), zone [7, 10)
  auto pick = [&](int lo, int hi) {
    int best = lo;
    for (int i = lo + 1; i < hi; ++i)
      if (count[i] > count[best]) best = i;
    return best;
  };
  if (count[pick(0, 3)] == 0) return site;  // no prostate zone tag in the notch
  anatomy::ProstateZoneTag t;
  t.level = static_cast<anatomy::ProstateLevel>(pick(0, 3));
  t.side = static_cast<anatomy::ProstateSide>(pick(3, 5) - 3);
  t.lateral = pick(5, 7) == 6;
  t.zone = static_cast<anatomy::ProstateZone>(pick(7, 10) - 7);
  site.label = anatomy::zone_label(t);
  return site;
}

}  // namespace ps
