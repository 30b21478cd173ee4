// Needle-tissue forces of one substep (paper §4.2.1, Algorithm 2: computeTissueForces,
// computeVirtualElasticForce, stick/slide, redistribute). Forces go straight onto the particles
// (State::f, before integration); the opposite of each is summed on the needle.
#include <algorithm>
#include <cmath>

#include "engine/tools/needle/needle_internal.h"

namespace ps {

namespace {

// Inverse distance weight of eq. 5/6; distances inside the needle's radius count as the radius
// (the needle has a size; and d = 0 would otherwise give an infinite weight).
inline double idw(double dist, double radius) { return 1.0 / std::max(dist, radius); }

}  // namespace

Vec3 apply_needle_tissue_forces(NeedleTool::Needle& nd, const Model& m, State& s, const std::vector<double>& puncture_kc,
                                const MembraneFaces& mf, double h, NeedleEventRing& events) {
  const Vec3 d = nd.d;
  Vec3 on_needle = Vec3::Zero();
  NeedleReadout& ro = nd.ro;
  ro.press_force = ro.cutting_force = ro.friction_force = 0.0;

  // the press damper acts above this approach speed only [m/s]: below it (a needle held still, or
  // creeping) the plain spring, which comes to rest (the damper on the needle's own coupling
  // vibration kept needle and tissue in a chatter, Needle.HeldStillInsideTissueEverythingComesToRest)
  constexpr double kDampedApproach = 0.05;
  // --- puncture: the tip pushes the entry face it has reached until the eq. 5 threshold breaks it
  nd.breached_now = -1;
  if (nd.press_n > 0) {
    double Cp = 0.0;
    for (int i = 0; i < nd.press_n; ++i) Cp += nd.press_w[i] * puncture_kc[m.component_of[nd.press_idx[i]]];
    // The tip's contact force on the wall: the penetration spring k (press_stiffness) on the
    // patch's effective mass M, critically damped on the approach speed of tip and patch: a sharp
    // tip indents the surface, it does not bounce off it. Quasi-statically the damper vanishes;
    // the faster the tip, the sooner the contact force reaches the threshold (at impact it is
    // about 2 sqrt(k M) times the speed), so the wall ruptures after a smaller deflection, as
    // measured (Mahvash & Dupont, IEEE TBME 57:934, 2010: rupture force and deflection before
    // rupture fall with insertion speed). Undamped, the explicit spring kicked the light patch
    // ahead of the tip, the contact chattered and a fast tip swept the wall along below the
    // threshold. M: the weighted force P w_i changes the patch velocity sum_i w_i v_i . d at the
    // rate P sum_i w_i^2 / m_i; the damping is capped at M / h (the speeds matched in one substep).
    double inv_m = 0.0, v_patch = 0.0;
    for (int i = 0; i < nd.press_n; ++i) {
      const int p = nd.press_idx[i];
      inv_m += nd.press_w[i] * nd.press_w[i] * m.inv_mass[p];
      v_patch += nd.press_w[i] * s.v[p].dot(d);
    }
    double P = nd.spec.press_stiffness * (-nd.press_a);
    // the damper acts only in contact and while the tip advances into the wall: a needle held
    // still (or pulled back) against a surface gets the plain spring, which comes to rest (the
    // damper on the patch's own speed alone kept needle and tissue in a chatter)
    P = std::max(0.0, P);  // a contact pushes, it never pulls
    if (inv_m > 0.0 && P > 0.0 && nd.V.dot(d) > kDampedApproach) {
      const double M = 1.0 / inv_m;
      const double c = std::min(2.0 * std::sqrt(nd.spec.press_stiffness * M), M / h);
      P = std::max(0.0, P + c * (nd.V.dot(d) - v_patch));
    }
    if (P >= Cp) {
      P = Cp;
      nd.breached_now = nd.press_component;
      nd.entered[nd.press_component] = 1;
      if (mf.sheet[nd.press_component]) {
        // a wall is torn where the tip went through: the faces around the crossed face
        for (int v : nd.press_face)
          for (int k = mf.start[v]; k < mf.start[v + 1]; ++k) nd.face_breached[mf.list[k]] = 1;
        if (nd.press_component == nd.lumen && nd.in_lumen) {
          // out of the lumen: the shaft beyond the hole meets the tissue from the next substep
          nd.in_lumen = false;
          nd.exit_a = nd.press_a;
          nd.exit_point = nd.T + nd.press_a * d;
        }
      }
    }
    for (int i = 0; i < nd.press_n; ++i) s.f[nd.press_idx[i]] += (P * nd.press_w[i]) * d;
    on_needle -= P * d;
    ro.press_force = P;
  }

  // --- cutting (eq. 5): only while the tip moves forward inside tissue. The gate is the axial
  // speed low-passed over a few milliseconds, and it is solved together with the needle's new
  // velocity (move_needle), not read from the last substep: below cut_velocity the gate is a
  // damper of k_c / cut_velocity (1.5 N over 1 mm/s = 1500 N s/m on a 10 g needle), far beyond
  // what an explicit step can hold. Read explicitly (the instantaneous speed, then its low-pass)
  // it made a needle held still inside tissue chatter in a two-substep cycle, the cutting force
  // on and off, its tick average off by a quarter at 3 substeps per 2 ms tick. Here the zone
  // and the force at full speed; apply_needle_cutting puts the solved part on the particles.
  nd.cut_share_n = 0;
  nd.cut_full = 0.0;
  const bool inside = nd.zone_n[0] > 0 || (nd.node_count > 1 && nd.zone_n[1] > 0);
  if (inside) {
    // the cutting zone, or the tip node's zone when the tip is between particle layers
    // (walls modelled as sheets are punctured, never cut: their particles in the tip node's zone
    // rub the shaft, they take no cutting force; cutting them pushed an intact wall ahead of the tip)
    const bool own = nd.cut_n > 0;
    const int n = own ? nd.cut_n : nd.zone_n[0] > 0 ? nd.zone_n[0] : nd.zone_n[1];
    const int* idx = own ? nd.cut_idx.data() : &nd.zone_idx[nd.zone_n[0] > 0 ? 0 : kZoneCapacity];
    auto cuttable = [&](int p) {
      const int c = m.component_of[p];
      return own || !(mf.sheet[c] && puncture_kc[c] > 0.0);
    };
    double W = 0.0, WK = 0.0;
    for (int i = 0; i < n; ++i) {
      const int p = idx[i];
      if (!cuttable(p)) continue;
      const double w = idw((s.x[p] - nd.T).norm(), nd.radius);
      W += w;
      WK += w * m.k_c[p];
      nd.cut_share_idx[nd.cut_share_n] = p;
      nd.cut_share[nd.cut_share_n++] = w * m.k_c[p];
    }
    if (WK > 0.0) {
      nd.cut_full = WK / W;  // eq. 5
      for (int i = 0; i < nd.cut_share_n; ++i) nd.cut_share[i] /= WK;
    } else {
      nd.cut_share_n = 0;
    }
  }

  // --- friction (eq. 6) and stick/slip through the virtual tissue particles
  int engaged = 0, stuck_count = 0;
  for (int j = 0; j < nd.node_count; ++j) {
    AffineAnchor& an = nd.anchors[j];
    const int n = nd.zone_n[j];
    if (n == 0) {
      an.reset();
      nd.stuck[j] = 1;
      nd.reported[j] = 255;
      nd.pending[j] = 0;
      continue;
    }
    const int* zi = &nd.zone_idx[static_cast<size_t>(j) * kZoneCapacity];
    const double* zd = &nd.zone_dist[static_cast<size_t>(j) * kZoneCapacity];
    const Vec3 X = needle_node(nd, j);
    // the anchor was (re)built on this zone by prepare_needle_anchors; its spring stiffness is
    // lowered where the summed coupling of all needles would exceed the stability bound
    const double kv = nd.spec.stick_stiffness * nd.stick_scale[j];
    double W = 0.0, WK = 0.0;
    for (int i = 0; i < n; ++i) {
      const double w = idw(zd[i], nd.radius);
      W += w;
      WK += w * m.k_f[zi[i]];
    }
    const double Fk = nd.node_scale * WK / W;  // eq. 6, per node length
    const double Fs = nd.spec.static_ratio * Fk;
    // a change of scale changes the stiffness, not the force the spring holds: its rest point
    // (the anchor offset) moves so that the force is continuous (a jump of the held force when
    // an anchor elsewhere appeared kicked a resting needle into a stick-slip cycle)
    if (nd.stick_scale[j] != nd.stick_scale_used[j]) {
      an.offset += (nd.stick_scale_used[j] / nd.stick_scale[j] - 1.0) * (an.evaluate(s.x) - X);
      nd.stick_scale_used[j] = nd.stick_scale[j];
    }
    Vec3 Fv = kv * (an.evaluate(s.x) - X);  // virtual elastic force on the node
    const double fa = Fv.dot(d);
    const double threshold = nd.stuck[j] ? Fs : Fk;
    if (std::abs(fa) > threshold) {
      // slide: the anchor moves along the shaft so the axial force is the kinetic friction
      const double target = fa > 0.0 ? Fk : -Fk;
      const double excess = fa - target;
      an.offset -= (excess / kv) * d;
      Fv -= excess * d;
      nd.stuck[j] = 0;
    } else {
      nd.stuck[j] = 1;
    }
    on_needle += Fv;
    an.add_reaction(s.f, s.x, Fv);
    ro.friction_force -= Fv.dot(d);
    ++engaged;
    stuck_count += nd.stuck[j];
    // stick <-> slip events once the new state has held for `debounce` substeps
    if (nd.reported[j] == 255) {
      if (++nd.pending[j] >= nd.debounce) { nd.reported[j] = nd.stuck[j]; nd.pending[j] = 0; }
    } else if (nd.stuck[j] != nd.reported[j]) {
      if (++nd.pending[j] >= nd.debounce) {
        nd.reported[j] = nd.stuck[j];
        nd.pending[j] = 0;
        push_event(events, nd, nd.stuck[j] ? NeedleEventKind::Stick : NeedleEventKind::Slip, s.time, X, m.component_of[zi[0]], j);
      }
    } else {
      nd.pending[j] = 0;
    }
  }
  ro.engaged_nodes = engaged;
  ro.stuck_nodes = stuck_count;
  return on_needle;  // the read-out's tissue and axial force are set with the cutting (apply_needle_cutting)
}

void apply_needle_cutting(NeedleTool::Needle& nd, State& s, const Vec3& f_other, double cut, NeedleEventRing& events) {
  const Vec3 d = nd.d;
  NeedleReadout& ro = nd.ro;
  for (int i = 0; i < nd.cut_share_n; ++i) s.f[nd.cut_share_idx[i]] += (cut * nd.cut_share[i]) * d;
  ro.cutting_force = cut;
  ro.tissue_force = f_other - cut * d;
  ro.axial_force = -ro.tissue_force.dot(d);
  nd.peak_force = std::max(nd.peak_force, ro.axial_force);
  if (nd.breached_now >= 0) {
    NeedleEvent e;
    e.kind = NeedleEventKind::Puncture;
    e.needle = nd.index;
    e.time = s.time;
    e.position = nd.T;
    e.depth = insertion_depth(nd);
    e.force = nd.peak_force;
    e.value = ro.press_force;   // the contact force on the wall at rupture [N]
    e.component = nd.breached_now;
    events.push(e);
    nd.peak_force = 0.0;
  }
}

}  // namespace ps
