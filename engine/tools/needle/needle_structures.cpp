// Structures a needle must not reach, watched between substeps: the urethra, a centre line
// carried by the gland (its wall is not modelled: the tip is "in the urethra" within the radius).
#include <algorithm>
#include <limits>

#include "engine/model/role.h"
#include "engine/tools/needle/needle_internal.h"

namespace ps {

namespace {

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

constexpr double kUrethraRearm = 1e-3;  // a tip this far beyond the radius may give a new event [m]

}  // namespace

void NeedleTool::set_urethra(const std::vector<Vec3>& centre_line, double radius) {
  const Model& m = *model_;
  urethra_rest_.clear();
  urethra_carrier_.clear();
  if (centre_line.size() < 2 || !(radius > 0.0)) return;
  for (const Vec3& q : centre_line) {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (size_t c = 0; c < m.components.size(); ++c) {
      if (m.components[c].role != Role::Prostate) continue;
      const Component& cc = m.components[c];
      for (int p = cc.first_particle; p < cc.first_particle + cc.particle_count; ++p) {
        const double d2 = (m.rest_pos[p] - q).squaredNorm();
        if (d2 < best_d2) { best_d2 = d2; best = p; }
      }
    }
    if (best < 0) { urethra_rest_.clear(); urethra_carrier_.clear(); return; }  // no gland: not watched
    urethra_rest_.push_back(q);
    urethra_carrier_.push_back(best);
  }
  urethra_now_.assign(urethra_rest_.size(), Vec3::Zero());
  urethra_radius_ = radius;
}

void NeedleTool::check_urethra(const Model& m, const State& s) {
  bool ready = false;
  for (auto& p : needles_) {
    Needle& nd = *p;
    if (!nd.contacted && !nd.near_urethra) continue;
    if (!ready) {
      for (size_t k = 0; k < urethra_rest_.size(); ++k) {
        const int q = urethra_carrier_[k];
        urethra_now_[k] = urethra_rest_[k] + (s.x[q] - m.rest_pos[q]);
      }
      ready = true;
    }
    double dist = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k + 1 < urethra_now_.size(); ++k)
      dist = std::min(dist, point_segment_distance(nd.T, urethra_now_[k], urethra_now_[k + 1]));
    if (!nd.near_urethra && dist < urethra_radius_) {
      nd.near_urethra = true;
      push_event(events_, nd, NeedleEventKind::Urethra, s.time, nd.T, -1, -1, dist);
    } else if (nd.near_urethra && dist > urethra_radius_ + kUrethraRearm) {
      nd.near_urethra = false;
    }
  }
}

}  // namespace ps
