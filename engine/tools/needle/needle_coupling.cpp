// Stability bound of the needle-tissue coupling (virtual tissue particles, paper §4.2.1).
//
// Each node's virtual particle is a spring of stiffness k (stick_stiffness) between the node and
// the attractor P*(x) its anchor computes from a few tissue particles; the spring acts on those
// particles through dP*/dx (AffineAnchor::add_reaction). It is integrated explicitly with the
// tissue, so it adds k J^T J to the tissue's stiffness. One needle adds little, but a particle
// can be held by many nodes: the zone radius (one lattice spacing, 10 mm in fat) reaches ~5
// nodes of each needle, and in a brachytherapy template (5 mm pitch) a particle near the
// capsule sits in the zones of several needles. In the default anatomy with 20 needles a fat
// particle next to the apex can be held by ~40 anchors summing to K h^2 / m ~ 2 (the limit of
// symplectic Euler is 4 for a lone spring, less with the tissue's own stiffness), enough to blow
// the apex up without a bound.
//
// The bound: for anchor A with stiffness k_A, c_A,q = |dP*/dx_q| (its weight |w_q|: the anchor is
// linear, needle_anchor.h) and C_A = sum_q c_A,q; block Gershgorin on M^-1 K gives
//   lambda_max(M^-1 K_needles) <= max_q G_q,  G_q = sum_{A holding q} k_A c_A,q C_A / m_q.
// Each anchor's stiffness is scaled by s_A = min(1, min_{q in A} kCouplingBudget / (G_q h^2)),
// so that afterwards G_q h^2 <= kCouplingBudget (2, half the limit 4 of a lone spring under
// symplectic Euler) for every particle. The tissue's own stiffness is not in the budget: where
// the needles gather it is fat (3 kPa), whose shape-memory springs are ~1e-3 of the limit; the
// Gershgorin bound is itself pessimistic (the 1-needle block tests at h = 1 ms reach G h^2 =
// 1.25 and are stable), and a tighter budget (0.75) softened those springs and turned the
// resting needle of Needle.HeldStillInsideTissueEverythingComesToRest into a stick-slip cycle.
// A scaled spring is softer, not weaker: the stick threshold is a force, the node still sticks
// and slips at the same friction, after a larger relative displacement; and its held force is
// continuous across a change of scale (needle_forces.cpp moves its rest point).
// Cost: proportional to the anchors (zones), not to the scene; no allocation.
#include <algorithm>

#include "engine/tools/needle/needle_internal.h"

namespace ps {

void prepare_needle_anchors(NeedleTool::Needle& nd, const State& s) {
  for (int j = 0; j < nd.node_count; ++j) {
    AffineAnchor& an = nd.anchors[j];
    const int n = nd.zone_n[j];
    if (n == 0) {
      an.reset();
      continue;
    }
    const int* zi = &nd.zone_idx[static_cast<size_t>(j) * kZoneCapacity];
    // (re)anchor when an anchor particle left the zone: coordinates on the current zone
    // particles (nearest first), the attractor kept where it was so the force is continuous
    bool rebuild = !an.valid();
    for (int a = 0; a < an.count && !rebuild; ++a) {
      bool found = false;
      for (int i = 0; i < n && !found; ++i) found = zi[i] == an.idx[a];
      rebuild = !found;
    }
    if (!rebuild && !an.rotational && n >= 3 && an.count < std::min(n, kAnchorMaxNeighbours)) rebuild = true;
    if (rebuild) {
      const Vec3 X = needle_node(nd, j);
      const Vec3 keep = an.valid() ? an.evaluate(s.x) : X;
      an.build(X, zi, n, s.x, keep);
    }
  }
}

namespace {

// c_a = |dP*/dx_a| = |w_a| of the anchor (P* is linear in x), for each of its particles; returns the sum.
double anchor_jacobian_bound(const AffineAnchor& an, double* c) {
  double sum = 0.0;
  for (int a = 0; a < an.count; ++a) sum += (c[a] = std::abs(an.w[a]));
  return sum;
}

}  // namespace

void bound_needle_coupling(std::vector<std::unique_ptr<NeedleTool::Needle>>& needles, const Model& m,
                           double dt, CouplingBudget& b) {
  for (int q : b.touched) b.g[q] = 0.0;
  b.touched.clear();
  b.peak = b.after = 0.0;
  b.softened = 0;
  // 1. G_q summed over every node of every needle (scale 1)
  for (auto& p : needles) {
    NeedleTool::Needle& nd = *p;
    const double k = nd.spec.stick_stiffness;
    for (int j = 0; j < nd.node_count; ++j) {
      nd.stick_scale[j] = 1.0;
      const AffineAnchor& an = nd.anchors[j];
      if (!an.valid()) continue;
      double* c = &nd.anchor_c[static_cast<size_t>(j) * kAnchorMaxNeighbours];
      const double C = anchor_jacobian_bound(an, c);
      nd.anchor_csum[j] = C;
      for (int a = 0; a < an.count; ++a) {
        const int q = an.idx[a];
        const double add = k * c[a] * C * m.inv_mass[q];
        if (!(add > 0.0)) continue;
        if (b.g[q] == 0.0) b.touched.push_back(q);  // each particle once: capacity n suffices
        b.g[q] += add;
      }
    }
  }
  const double h2 = dt * dt;
  for (int q : b.touched) b.peak = std::max(b.peak, b.g[q] * h2);
  if (b.peak <= kCouplingBudget) {
    b.after = b.peak;
    return;
  }
  // 2. each node's spring scaled by its most loaded particle's share of the budget
  const double g_max = kCouplingBudget / h2;
  for (auto& p : needles) {
    NeedleTool::Needle& nd = *p;
    for (int j = 0; j < nd.node_count; ++j) {
      const AffineAnchor& an = nd.anchors[j];
      if (!an.valid()) continue;
      double scale = 1.0;
      for (int a = 0; a < an.count; ++a) {
        const double g = b.g[an.idx[a]];
        if (g > g_max) scale = std::min(scale, g_max / g);
      }
      nd.stick_scale[j] = scale;
      b.softened += scale < 1.0;
    }
  }
  // 3. the bound after scaling (read-out; <= kCouplingBudget by construction)
  for (int q : b.touched) b.g[q] = 0.0;
  for (auto& p : needles) {
    NeedleTool::Needle& nd = *p;
    const double k = nd.spec.stick_stiffness;
    for (int j = 0; j < nd.node_count; ++j) {
      const AffineAnchor& an = nd.anchors[j];
      if (!an.valid()) continue;
      const double* c = &nd.anchor_c[static_cast<size_t>(j) * kAnchorMaxNeighbours];
      for (int a = 0; a < an.count; ++a)
        if (m.inv_mass[an.idx[a]] > 0.0) b.g[an.idx[a]] += nd.stick_scale[j] * k * c[a] * nd.anchor_csum[j] * m.inv_mass[an.idx[a]];
    }
  }
  for (int q : b.touched) b.after = std::max(b.after, b.g[q] * h2);
}

}  // namespace ps
