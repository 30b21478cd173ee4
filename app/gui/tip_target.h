// The live tip-target figure of a needle in the metrics panel: the distance from the tip to its
// target (carried by the tissue) at the needle's deepest point so far, the moment the session
// score measures (SessionMetrics: the tip at the tick of its deepest planned depth). While the
// needle advances it follows the tip; once the needle is drawn back it holds, so a brachytherapy
// needle withdrawn while its seeds drop keeps its targeting error instead of showing how far it
// has been pulled back.
#pragma once

namespace ps::gui {

struct TipTargetHold {
  static constexpr double kWithdrawn = 2e-3;  // drawn back this far: the figure is "held" [m]
  double deepest = -1.0;                      // [m], < 0: not in tissue yet
  double at_deepest_mm = 0.0;
  // One frame: depth since first contact [m] and the tip-target distance now [mm]; returns the
  // figure to show.
  double update(double depth_m, double distance_mm) {
    if (depth_m >= deepest) {
      deepest = depth_m;
      at_deepest_mm = distance_mm;
    }
    return at_deepest_mm;
  }
  bool held(double depth_m) const { return deepest > 0.0 && deepest - depth_m > kWithdrawn; }
  bool measured() const { return deepest > 0.0; }
};

}  // namespace ps::gui
