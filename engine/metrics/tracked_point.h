// A material point of the tissue followed through its motion: a needle's target, a seed's planned
// site, a urethra vertex. Built once from the rest configuration on the nearest particles of the
// organ that holds the point, with the paper's discrete deformation coordinates (AffineAnchor,
// §3.2.3), so it follows the tissue's translation, rotation and local deformation. Evaluating
// never allocates (metrics are fed after every tick).
#pragma once
#include <string>
#include <vector>

#include "engine/model/model.h"
#include "engine/tools/needle/needle_anchor.h"

namespace ps {

// The deformable component whose particles hold rest point X: the component of the nearest
// non-rigid particle, provided X lies within 0.75 x that component's spacing of it (inside the
// lattice, not in the gap between organs or outside the scene); -1 otherwise (editor check
// "target outside every organ").
int component_holding(const Model& m, const Vec3& X);

struct TrackedPoint {
  Vec3 rest = Vec3::Zero();        // [m]
  int component = -1;              // organ holding it, -1: outside every organ (follows nothing)
  AffineAnchor anchor;
  // Current position [m] (the rest point itself when outside every organ).
  Vec3 position(const std::vector<Vec3>& x) const { return anchor.valid() ? anchor.evaluate(x) : rest; }
};

// Anchors X on the kAnchorMaxNeighbours nearest particles of the organ holding it (at rest).
TrackedPoint track_point(const Model& m, const Vec3& X);

// Winding number of the closed surface `surf` around p with particle positions x: ~1 inside,
// ~0 outside (robust to the small gaps and folds of a deformed lattice surface).
double winding_number(const Surface& surf, const std::vector<Vec3>& x, const Vec3& p);

}  // namespace ps
