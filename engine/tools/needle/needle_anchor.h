// A point held by a few tissue particles, built at run time: the virtual tissue particle of a
// needle node (paper §4.2.1) and an embedded brachytherapy seed both use it. Fixed-size storage:
// building and evaluating never allocate.
//
// For a point X and neighbours N_1..N_k (k <= kAnchorMaxNeighbours) the anchor keeps one weight
// per neighbour, affine-reproducing and of least norm (needle_anchor.cpp):
//   P*(x) = sum_a w_a x_a + offset,   sum_a w_a = 1,   sum_a w_a N_a = X (within their span),
// so its attractor follows the tissue's translation, rotation and local deformation, and is
// linear in x: a force held on it adds no stiffness of its own (the paper's §3.2.3 coordinates,
// with their beta n/|n| terms, would; docs/robustness.md "The needle's virtual particles").
// Fallback: coincident or collinear neighbours (one or two particles in a zone), or weights that
// extrapolate (leave [-kAnchorWeightMargin, 1 + kAnchorWeightMargin]: X beside its particles
// rather than among them): the anchor follows the tissue by translation only, w_a normalised
// inverse distances and offset = X - sum w_a x_a (for one particle, a rigid attachment).
// `rotational` says which form is in use.
// `offset` also carries the re-anchoring continuity: rebuilding on other particles keeps P*
// where it was, so a virtual force does not jump when zone membership changes.
#pragma once
#include <array>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

inline constexpr int kAnchorMaxNeighbours = 6;
// An anchor whose mean weights leave [-margin, 1 + margin] extrapolates (X outside the particles
// that hold it: one side of a hole in a wall) and takes the translation-only form instead
// (needle_anchor.cpp).
inline constexpr double kAnchorWeightMargin = 0.5;
// Eigenvalues of the anchor's moment matrix below this fraction of the largest are dropped
// (particles in a plane or on a line, needle_anchor.cpp).
inline constexpr double kAnchorRankTolerance = 1e-6;

struct AffineAnchor {
  int count = 0;                                    // neighbours in use (0: not built)
  std::array<int, kAnchorMaxNeighbours> idx{};      // particle indices
  std::array<double, kAnchorMaxNeighbours> w{};     // linear weights, sum 1
  Vec3 offset = Vec3::Zero();                       // [m]
  bool rotational = false;                          // affine form (true) or translation fallback

  bool valid() const { return count > 0; }
  void reset() { count = 0; offset.setZero(); rotational = false; }
  // Weights of X w.r.t. particles ids[0..n) (n clipped to kAnchorMaxNeighbours) at
  // positions x, then offset set so that evaluate(x) == keep (keep = X for a fresh anchor).
  void build(const Vec3& X, const int* ids, int n, const std::vector<Vec3>& x, const Vec3& keep);
  // Attractor position P*(x) [m].
  Vec3 evaluate(const std::vector<Vec3>& x) const;
  // Adds the reaction of a force F acting on the anchored point to the particles, -w_a F (the
  // exact gradient -(dP*/dx_a)^T F), so the pair conserves linear momentum.
  void add_reaction(std::vector<Vec3>& f, const std::vector<Vec3>& x, const Vec3& F) const;
  // Weighted particle velocity sum w_a v_a [m/s].
  Vec3 velocity(const std::vector<Vec3>& v) const;
  bool uses(int particle) const {
    for (int a = 0; a < count; ++a)
      if (idx[a] == particle) return true;
    return false;
  }
};

}  // namespace ps
