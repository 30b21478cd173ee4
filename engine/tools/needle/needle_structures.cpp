// Structures a needle must not reach, watched once per tick: the urethra, a centre line carried by
// the gland (its wall is not modelled: the tip is "in the urethra" within the radius), and the
// gland's far side (a tip that went in through the capsule and is out of the gland again).
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
// a tip out of the gland is back in, and may leave it again (a new event), only this far inside its
// surface along the needle [m]: nearer, the tented capsule sliding over the tip gives a second exit
constexpr double kGlandRearm = 2e-3;

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

void NeedleTool::set_gland(int component) {
  const bool surfaced = component >= 0 && component < static_cast<int>(puncture_kc_.size()) && puncture_kc_[component] > 0.0 &&
                        !membranes_->sheet[component];
  gland_ = surfaced ? component : -1;
}

// Whether the tip is in the gland, by the shaft's crossings of the gland's surface from the hub
// (outside: in the rectum or the probe's guide) to the tip: an entry face (normal against the
// needle) counts +1, an exit face -1. The faces are those of the tube's gland particles: a face
// the axis crosses has its corners within a tissue spacing of it, inside the tube's margin.
// A crossing counts once (the same axial position), whether a face is met from several of its
// corners or the axis passes on an edge shared by two faces. Once per tick:
// the GlandExit event and entered[gland] = 2 until the tip is back in, kGlandRearm deep.
void NeedleTool::check_gland_exit(const Model& m, State& s) {
  const MembraneFaces& mf = *membranes_;
  const int g = gland_;
  for (auto& p : needles_) {
    Needle& nd = *p;
    if (!nd.contacted || nd.entered[g] == 0) continue;
    const Vec3 T = nd.T, d = nd.d;
    const double shaft = (nd.node_count - 1) * nd.spec.node_spacing;
    int n_cross = 0;
    int sum = 0;
    bool exits = false, near_exit_ahead = false;
    for (int q : nd.tracked) {
      if (m.component_of[q] != g || !m.on_surface[q]) continue;
      for (int k = mf.start[q]; k < mf.start[q + 1]; ++k) {
        const int f = mf.list[k];
        const auto& fc = mf.faces[f];
        const Vec3 &A = s.x[fc[0]], &B = s.x[fc[1]], &C = s.x[fc[2]];
        const Vec3 e1 = B - A, e2 = C - A;
        double t = 0.0;  // the crossing's axial position relative to the tip [m]
        if (!axis_crosses_triangle(T, d, A, e1, e2, 0.0, t)) continue;
        if (t > kGlandRearm || t < -shaft) continue;
        const bool entry = e1.cross(e2).dot(d) < 0.0;
        if (t > 0.0) {  // ahead of the tip: an exit face this near means the tip is at the capsule
          near_exit_ahead |= !entry;
          continue;
        }
        bool seen = false;
        for (int i = 0; i < n_cross; ++i) seen |= gland_cross_t_[static_cast<size_t>(i)] == t;
        if (seen || n_cross >= static_cast<int>(gland_cross_t_.size())) continue;
        gland_cross_t_[static_cast<size_t>(n_cross++)] = t;
        sum += entry ? 1 : -1;
        exits |= !entry;
      }
    }
    // out: the shaft has left through a face since it last came in; a tip whose entry face the
    // tube does not hold (a needle that started in the gland) stays in until it crosses an exit
    const bool outside = exits && sum <= 0;
    if (outside && nd.entered[g] == 1) {
      nd.entered[g] = 2;
      push_event(events_, nd, NeedleEventKind::GlandExit, s.time, nd.T, g);
    } else if (!outside && !near_exit_ahead && nd.entered[g] == 2) {
      nd.entered[g] = 1;
    }
  }
}

}  // namespace ps
