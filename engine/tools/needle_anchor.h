// A point held by a few tissue particles through discrete deformation coordinates (paper
// §3.2.3), built at run time: the virtual tissue particle of a needle node (§4.2.1) and an
// embedded brachytherapy seed both use it. Fixed-size storage: building and evaluating never
// allocate.
//
// For a point X and neighbours N_1..N_k (k <= kAnchorMaxNeighbours) every valid triplet t gives
// X = alpha_i N_i + alpha_j N_j + alpha_k N_k + beta_t n_t/|n_t|; the anchor keeps the mean
// over the m valid triplets (one weight per neighbour, and the triplets with beta != 0), so its
// attractor follows the tissue's translation, rotation and local deformation:
//   P*(x) = sum_a w_a x_a + sum_t b_t n_t(x)/|n_t(x)| + offset.
// Fallback: with fewer than 3 non-collinear neighbours (thin tissue, zone edges, one or two
// particles in a zone) no triplet is valid; the anchor then follows the tissue by translation
// only: w_a are normalised inverse distances and offset = X - sum w_a x_a (for one particle
// this is a rigid attachment to it). The same fallback when the mean weights extrapolate (leave
// [-kAnchorWeightMargin, 1 + kAnchorWeightMargin]: X beside its particles rather than among
// them). `rotational` says which form is in use.
// `offset` also carries the re-anchoring continuity: rebuilding on other particles keeps P*
// where it was, so a virtual force does not jump when zone membership changes.
#pragma once
#include <array>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

inline constexpr int kAnchorMaxNeighbours = 6;
inline constexpr int kAnchorMaxTriplets = 20;   // C(6, 3)
// An anchor whose mean weights leave [-margin, 1 + margin] extrapolates (X outside the particles
// that hold it: one side of a hole in a wall) and takes the translation-only form instead
// (needle_anchor.cpp).
inline constexpr double kAnchorWeightMargin = 0.5;

struct AnchorTriplet {
  int i, j, k;                     // particle indices
  double b;                        // beta_t / m [m]
};

struct AffineAnchor {
  int count = 0;                                    // neighbours in use (0: not built)
  std::array<int, kAnchorMaxNeighbours> idx{};      // particle indices
  std::array<double, kAnchorMaxNeighbours> w{};     // linear weights, sum 1
  int nbeta = 0;
  std::array<AnchorTriplet, kAnchorMaxTriplets> beta{};
  Vec3 offset = Vec3::Zero();                       // [m]
  bool rotational = false;                          // discrete coordinates (true) or translation fallback

  bool valid() const { return count > 0; }
  void reset() { count = 0; nbeta = 0; offset.setZero(); rotational = false; }
  // Coordinates of X w.r.t. particles ids[0..n) (n clipped to kAnchorMaxNeighbours) at
  // positions x, then offset set so that evaluate(x) == keep (keep = X for a fresh anchor).
  void build(const Vec3& X, const int* ids, int n, const std::vector<Vec3>& x, const Vec3& keep);
  // Attractor position P*(x) [m].
  Vec3 evaluate(const std::vector<Vec3>& x) const;
  // Adds the reaction of a force F acting on the anchored point to the particles: the exact
  // gradient -(dP*/dx_a)^T F (linear part -w_a F, plus the normals' derivative as in
  // engine/step/shape_memory.cpp), so the pair conserves linear momentum.
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
