// Zones of interest (paper §4.2.1, Fig. 7). The particles near the needle are kept in a tube
// around the shaft (from the hub to a little ahead of the tip, zone radius + one tissue spacing).
// Each substep the tube is rebuilt from the previous one: members still inside are kept, then
// their CSR neighbours are tested, and the neighbours of every newcomer, until no neighbour
// enters (a flood fill confined to the tube). Its cost is proportional to the tube's content,
// not to the scene. The first contact, and components the neighbour graph does not connect, are
// found in the precomputed list of particles near the planned line, of which only the slice
// around the tip is tested (every substep before contact, every kPlanEvery substeps after).
// Zone membership is then a classification of the tube (see needle.h).
#include <algorithm>
#include <cmath>

#include "engine/tools/needle/needle_internal.h"

namespace ps {

namespace {

constexpr int kPlanEvery = 8;

// Keeps the k nearest: inserts (p, dist) into a fixed array holding n entries.
template <size_t K>
void keep_nearest(std::array<int, K>& idx, std::array<double, K>& dist, int& n, int p, double dp) {
  if (n < static_cast<int>(K)) {
    idx[n] = p;
    dist[n] = dp;
    ++n;
    return;
  }
  int far = 0;
  for (int i = 1; i < n; ++i)
    if (dist[i] > dist[far]) far = i;
  if (dp < dist[far]) { idx[far] = p; dist[far] = dp; }
}

}  // namespace

void update_needle_zones(NeedleTool::Needle& nd, const Model& m, const State& s, const std::vector<double>& puncture_kc,
                         const MembraneFaces& mf, NeedleEventRing& events) {
  const Vec3 T = nd.T, d = nd.d;
  const double sp = nd.spec.node_spacing;
  const double shaft = (nd.node_count - 1) * sp;
  const double ahead_max = nd.Rc + nd.halo;
  const double behind_max = shaft + nd.Rf + nd.halo;
  const double r_max = std::max({nd.Rc, nd.Rf, nd.notch_radius}) + nd.halo;
  const double r_max2 = r_max * r_max;
  // a face crossed farther behind the tip than this is not being pressed (the shaft passes
  // through a surface elsewhere); any press deeper than threshold / stiffness breaches anyway
  const double press_reach = mf.max_puncture / nd.spec.press_stiffness + nd.halo;
  int visited = 0, plan_checked = 0;
  auto in_tube = [&](int p) {
    ++visited;
    const Vec3 rel = s.x[p] - T;
    const double a = rel.dot(d);
    if (a > ahead_max || a < -behind_max) return false;
    return rel.squaredNorm() - a * a <= r_max2;
  };
  auto eligible = [&](int p) {
    return m.inv_mass[p] > 0.0 && m.components[m.component_of[p]].kind != ComponentKind::Rigid;
  };

  // 1. keep the members still in the tube
  nd.next.clear();
  for (int p : nd.tracked) {
    if (in_tube(p)) nd.next.push_back(p);
    else nd.mark[p] = 0;
  }
  // 2. the planned-line slice around the tip: first contact, unlinked components
  if (nd.next.empty() || ++nd.seed_counter >= kPlanEvery) {
    nd.seed_counter = 0;
    const double t_tip = (T - nd.spec.start).dot(nd.spec.direction);
    const double lo = t_tip - nd.spec.plan_margin - nd.halo, hi = t_tip + ahead_max + nd.spec.plan_margin;
    auto it = std::lower_bound(nd.plan_t.begin(), nd.plan_t.end(), lo);
    for (size_t k = static_cast<size_t>(it - nd.plan_t.begin()); k < nd.plan_t.size() && nd.plan_t[k] <= hi; ++k) {
      const int p = nd.plan_idx[k];
      if (nd.mark[p]) continue;
      ++plan_checked;
      if (in_tube(p)) { nd.mark[p] = 1; nd.next.push_back(p); }
    }
  }
  // 3. flood fill through CSR neighbours, confined to the tube
  for (size_t i = 0; i < nd.next.size(); ++i) {
    const int p = nd.next[i];
    for (int a = m.nbr_start[p]; a < m.nbr_start[p + 1]; ++a) {
      const int q = m.nbr[a];
      if (nd.mark[q] || !eligible(q)) continue;
      if (in_tube(q)) { nd.mark[q] = 1; nd.next.push_back(q); }
    }
  }
  std::swap(nd.tracked, nd.next);
  nd.stats.tracked = static_cast<int>(nd.tracked.size());
  nd.stats.visited = visited;
  nd.stats.plan_checked = plan_checked;

  // 4. the puncture zone: the nearest membrane face the axis crosses behind the tip. A volume
  // resists at its entry faces until it is entered; a sheet (a wall modelled as a surface:
  // rectum, bladder) from either side and again at its far wall, one torn hole at a time.
  nd.press_n = 0;
  nd.press_a = -press_reach;
  ++nd.epoch;
  // the wall of the lumen the needle started in: the crossings of the axis with it nearest behind
  // and ahead of the tip, torn or intact (where the shaft leaves the lumen; whether the tip is back)
  double lumen_behind = -1e300, lumen_ahead = 1e300;
  bool behind_torn = false, ahead_torn = false;
  for (int p : nd.tracked) {
    const int c = m.component_of[p];
    const bool sheet = mf.sheet[c] != 0;
    const bool lumen_wall = c == nd.lumen;
    if (!(puncture_kc[c] > 0.0) || !m.on_surface[p] || (!sheet && nd.entered[c])) continue;
    for (int k = mf.start[p]; k < mf.start[p + 1]; ++k) {
      const int f = mf.list[k];
      if (nd.face_epoch[f] == nd.epoch) continue;
      nd.face_epoch[f] = nd.epoch;
      if (sheet && nd.face_breached[f] && !lumen_wall) continue;
      const auto& fc = mf.faces[f];
      const Vec3 &A = s.x[fc[0]], &B = s.x[fc[1]], &C = s.x[fc[2]];
      const Vec3 e1 = B - A, e2 = C - A;
      if (!sheet && !(e1.cross(e2).dot(d) < 0.0)) continue;  // exit face or edge-on
      constexpr double tol = 1e-9;  // shared edges: a crossing is never lost between two faces
      double t = 0.0;  // the crossing's axial position
      if (!axis_crosses_triangle(T, d, A, e1, e2, tol, t)) continue;
      if (lumen_wall) {
        const bool torn = nd.face_breached[f] != 0;
        if (t < 0.0 && t > lumen_behind) { lumen_behind = t; behind_torn = torn; }
        if (t >= 0.0 && t < lumen_ahead) { lumen_ahead = t; ahead_torn = torn; }
        if (torn) continue;
      }
      if (t >= 0.0 || t < nd.press_a) continue;  // ahead of the tip, or not the nearest behind it
      nd.press_n = 1;
      nd.press_a = t;
      nd.press_face = fc;
      nd.press_face_id = f;
      nd.press_component = mf.face_component[f];
    }
  }
  // the membrane particles around the crossing share the press load (weights 1 - (r/R)^2)
  Vec3 X_press = Vec3::Zero();
  double R2_press = 0.0;
  if (nd.press_n > 0) {
    X_press = T + nd.press_a * d;
    const auto& fc = nd.press_face;
    double R = nd.Rc;
    for (int i = 0; i < 3; ++i) R = std::max(R, (s.x[fc[i]] - s.x[fc[(i + 1) % 3]]).norm());
    R2_press = R * R;
    nd.press_n = 0;
    double W = 0.0;
    for (int p : nd.tracked) {
      if (m.component_of[p] != nd.press_component || !m.on_surface[p]) continue;
      const double r2 = (s.x[p] - X_press).squaredNorm();
      if (r2 >= R2_press) continue;
      const double w = 1.0 - r2 / R2_press;
      if (nd.press_n < kPressCapacity) {
        nd.press_idx[nd.press_n] = p;
        nd.press_w[nd.press_n] = w;
        ++nd.press_n;
      } else {
        int low = 0;
        for (int i = 1; i < nd.press_n; ++i)
          if (nd.press_w[i] < nd.press_w[low]) low = i;
        if (w <= nd.press_w[low]) continue;
        W -= nd.press_w[low];
        nd.press_idx[low] = p;
        nd.press_w[low] = w;
      }
      W += w;
    }
    if (nd.press_n == 0 || !(W > 0.0)) {
      nd.press_n = 0;  // cannot happen with the face's own vertices inside R; kept safe
    } else {
      for (int i = 0; i < nd.press_n; ++i) nd.press_w[i] /= W;
    }
  }

  // out of the lumen through a hole, the hole is where the axis crosses a torn face of its wall
  // nearest behind the tip; retracted back in, a torn face is the nearest crossing ahead
  if (nd.lumen >= 0 && !nd.in_lumen) {
    if (behind_torn) {
      nd.exit_a = lumen_behind;
      nd.exit_point = T + lumen_behind * d;
    } else if (ahead_torn) {
      nd.in_lumen = true;
      if (nd.guided) reset_contact_in_lumen(nd, mf);  // back in the guide: the next pass starts afresh
    }
  }

  // 5. cutting and friction zones
  for (int j = 0; j < nd.node_count; ++j) nd.zone_n[j] = 0;
  nd.cut_n = 0;
  const double Rc2 = nd.Rc * nd.Rc;
  const double Rf2 = nd.Rf * nd.Rf;
  // tip in the lumen: only the pressed patch touches the needle (nothing is zoned)
  const bool shielded = nd.lumen >= 0 && nd.in_lumen;
  const bool through = nd.lumen >= 0 && !nd.in_lumen;
  for (int p : nd.tracked) {
    if (shielded) break;
    const int c = m.component_of[p];
    const bool membrane = puncture_kc[c] > 0.0;
    const bool sheet = mf.sheet[c] != 0;
    // through the lumen's wall: its particles rub the shaft only at the hole
    if (through && c == nd.lumen && (s.x[p] - nd.exit_point).squaredNorm() > Rf2) continue;
    // an intact volume's particles take nothing until it is entered (the needle is outside)
    if (membrane && !sheet && !nd.entered[c]) continue;
    // the pressed patch of a wall is pushed, not rubbed
    if (membrane && sheet && nd.press_n > 0 && c == nd.press_component && (s.x[p] - X_press).squaredNorm() < R2_press)
      continue;
    const Vec3 rel = s.x[p] - T;
    const double a = rel.dot(d);
    const double dist2 = rel.squaredNorm();
    if (a >= 0.0) {
      if (membrane && sheet) continue;  // walls are punctured, not cut
      if (dist2 <= Rc2) keep_nearest(nd.cut_idx, nd.cut_dist, nd.cut_n, p, std::sqrt(dist2));
      continue;
    }
    // behind the tip plane: friction zones of the nodes within Rf. Node j sits on the axis at
    // u_j = j sp behind the tip, so its distance is sqrt(r^2 + (u - u_j)^2) with r the particle's
    // distance from the axis: only the nodes with |u - u_j| <= sqrt(Rf^2 - r^2) can be in range,
    // none when r > Rf (three quarters of the tube). The window is widened by 1 nm, far above
    // the rounding of either form, and each node in it still takes the exact test below, so the
    // zones are those of testing every node within Rf along the axis (same members, same bits).
    const double u = -a;
    constexpr double kSlack = 1e-9;  // [m]
    const double reach2 = (nd.Rf + kSlack) * (nd.Rf + kSlack) - (dist2 - a * a);
    if (!(reach2 >= 0.0)) continue;
    const double w = std::min(nd.Rf, std::sqrt(reach2) + kSlack);  // axial half-window [m]
    const int j_lo = std::max(0, static_cast<int>(std::ceil((u - w) / sp)));
    int j_hi = std::min(nd.node_count - 1, static_cast<int>(std::floor((u + w) / sp)));
    // nodes behind the hole are in the lumen (or the probe's guide): tissue beyond the wall
    // does not reach them through it
    if (through && c != nd.lumen) j_hi = std::min(j_hi, static_cast<int>(std::floor(-nd.exit_a / sp)));
    for (int j = j_lo; j <= j_hi; ++j) {
      const double dj = (s.x[p] - needle_node(nd, j)).norm();
      if (dj > nd.Rf) continue;
      int* zi = &nd.zone_idx[static_cast<size_t>(j) * kZoneCapacity];
      double* zd = &nd.zone_dist[static_cast<size_t>(j) * kZoneCapacity];
      int& n = nd.zone_n[j];
      if (n < kZoneCapacity) {
        zi[n] = p;
        zd[n] = dj;
        ++n;
      } else {
        int far = 0;
        for (int i = 1; i < n; ++i)
          if (zd[i] > zd[far]) far = i;
        if (dj < zd[far]) { zi[far] = p; zd[far] = dj; }
      }
    }
  }
  // zone members nearest first (insertion sort of <= kZoneCapacity; ties by index: deterministic)
  for (int j = 0; j < nd.node_count; ++j) {
    int* zi = &nd.zone_idx[static_cast<size_t>(j) * kZoneCapacity];
    double* zd = &nd.zone_dist[static_cast<size_t>(j) * kZoneCapacity];
    for (int i = 1; i < nd.zone_n[j]; ++i)
      for (int k = i; k > 0 && (zd[k] < zd[k - 1] || (zd[k] == zd[k - 1] && zi[k] < zi[k - 1])); --k) {
        std::swap(zd[k], zd[k - 1]);
        std::swap(zi[k], zi[k - 1]);
      }
  }

  // first contact: the tip presses a surface or has tissue alongside it
  if (!nd.contacted && (nd.press_n > 0 || nd.zone_n[0] > 0 || (nd.node_count > 1 && nd.zone_n[1] > 0))) {
    nd.contacted = true;
    nd.contact_axial = T.dot(d);
    const int c = nd.press_n > 0 ? nd.press_component
                                 : m.component_of[nd.zone_n[0] > 0 ? nd.zone_idx[0] : nd.zone_idx[kZoneCapacity]];
    push_event(events, nd, NeedleEventKind::Contact, s.time, T, c);
  }
}

}  // namespace ps
