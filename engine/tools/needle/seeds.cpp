// Brachytherapy seeds (paper Fig. 2, 15). A needle carries seeds planned at depths along its
// path; while the needle is pulled back, a seed leaves the tip when the tip comes back to its
// planned depth (the stylet holds it while the cannula withdraws). It is embedded where it lands:
// an AffineAnchor (affine weights, needle_anchor.h) over the nearest tissue
// particles of the needle's tube, so it is carried by the tissue afterwards, rotation and local
// deformation included. Planned vs actual: planned = start + depth * direction.
// A seed is armed once the tip has come within kSeedArm of its planned depth: a needle that
// recoils on its way in (a surface giving way ahead of it, another needle's puncture nearby)
// moves back for a few substeps, and that is not the pull-back (it dropped every seed at the
// perineum in the two-needle brachytherapy scene). kSeedArm covers the tip's lag behind the
// command (coupling spring) when a seed is planned at the deepest scripted depth.
#include <algorithm>

#include "engine/tools/needle/needle_internal.h"

namespace ps {

namespace {
constexpr double kSeedArm = 2e-3;  // [m]
}  // namespace

void update_seeds(NeedleTool::Needle& nd, const Model& m, const State& s, NeedleEventRing& events) {
  if (nd.seeds.empty()) return;
  // carried by the tissue
  for (SeedState& sd : nd.seeds)
    if (sd.deposited && sd.embedded) sd.current = sd.anchor.evaluate(s.x);
  const double t_tip = plan_depth(nd);
  nd.deepest = std::max(nd.deepest, t_tip);
  const bool retracting = nd.V.dot(nd.d) < -1e-5;
  // a live DepositSeed command releases the next seed where the tip is, whatever the motion
  const bool requested = nd.deposit_request;
  nd.deposit_request = false;
  if (!retracting && !requested) return;
  bool request_left = requested;
  for (size_t k = 0; k < nd.seeds.size(); ++k) {
    SeedState& sd = nd.seeds[k];
    if (sd.deposited) continue;
    if (request_left) {
      request_left = false;
    } else if (!retracting || t_tip > sd.depth || nd.deepest < sd.depth - kSeedArm) {
      continue;
    }
    sd.deposited = true;
    sd.time = s.time;
    sd.at = nd.T;
    sd.current = nd.T;
    // nearest tissue particles of the tube within reach of the tip
    std::array<int, kAnchorMaxNeighbours> ids{};
    std::array<double, kAnchorMaxNeighbours> dist{};
    int n = 0;
    const double reach = nd.Rf + nd.halo;
    for (int p : nd.tracked) {
      const double dp = (s.x[p] - nd.T).norm();
      if (dp > reach) continue;
      if (n < kAnchorMaxNeighbours) { ids[n] = p; dist[n] = dp; ++n; continue; }
      int far = 0;
      for (int i = 1; i < n; ++i)
        if (dist[i] > dist[far]) far = i;
      if (dp < dist[far]) { ids[far] = p; dist[far] = dp; }
    }
    // nearest first, ties by index (deterministic)
    for (int i = 1; i < n; ++i)
      for (int j = i; j > 0 && (dist[j] < dist[j - 1] || (dist[j] == dist[j - 1] && ids[j] < ids[j - 1])); --j) {
        std::swap(dist[j], dist[j - 1]);
        std::swap(ids[j], ids[j - 1]);
      }
    sd.embedded = n > 0;
    if (sd.embedded) sd.anchor.build(nd.T, ids.data(), n, s.x, nd.T);
    push_event(events, nd, NeedleEventKind::Seed, s.time, nd.T, n > 0 ? m.component_of[ids[0]] : -1, -1, static_cast<double>(k));
  }
}

}  // namespace ps
