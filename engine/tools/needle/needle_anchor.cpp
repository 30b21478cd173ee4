#include "engine/tools/needle/needle_anchor.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace ps {

void AffineAnchor::build(const Vec3& X, const int* ids, int n, const std::vector<Vec3>& x, const Vec3& keep) {
  reset();
  n = std::min(n, kAnchorMaxNeighbours);
  if (n <= 0) return;
  count = n;
  for (int a = 0; a < n; ++a) { idx[a] = ids[a]; w[a] = 0.0; }
  // Affine-reproducing weights of least norm: sum_a w_a = 1 and sum_a w_a x_a = X within the span
  // of the particles. With c their centroid, d_a = x_a - c and S = sum_a d_a d_a^T:
  //   w_a = 1/n + d_a^T S^+ (X - c).
  // Linear in x, so a held force adds only k J^T J to the tissue's stiffness. (The paper's
  // coordinates, alpha and beta n/|n| of each triplet, make P* nonlinear: a stuck node's friction
  // force F then adds F . d2P*/dx2, a stiffness of either sign that the coupling bound cannot
  // scale away; beside the biopsy track it reached -3.9 / h^2 per unit mass and drove a prostate
  // particle to 7.8 m/s, docs/robustness.md.) Particles in a plane (a wall): S^+ drops the normal,
  // X's in-plane position is reproduced and its distance from the plane is carried by `offset`.
  Vec3 c = Vec3::Zero();
  for (int a = 0; a < n; ++a) c += x[idx[a]];
  c /= n;
  Mat3 S = Mat3::Zero();
  for (int a = 0; a < n; ++a) S += (x[idx[a]] - c) * (x[idx[a]] - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> es(S);
  const double top = es.eigenvalues().maxCoeff();
  Vec3 g = Vec3::Zero();  // S^+ (X - c)
  int rank = 0;
  for (int e = 0; e < 3; ++e) {
    const double lam = es.eigenvalues()[e];
    if (!(lam > kAnchorRankTolerance * top)) continue;
    g += (es.eigenvectors().col(e).dot(X - c) / lam) * es.eigenvectors().col(e);
    ++rank;
  }
  bool extrapolates = rank < 2;  // coincident or collinear particles: no frame to follow
  for (int a = 0; a < n && !extrapolates; ++a) {
    w[a] = 1.0 / n + (x[idx[a]] - c).dot(g);
    extrapolates |= w[a] < -kAnchorWeightMargin || w[a] > 1.0 + kAnchorWeightMargin;
  }
  // Extrapolating weights (X beside its particles, not among them: the nodes near a hole in a
  // wall, held by 3-4 wall particles on one side) reach 6 and -3; the spring's reaction is then
  // multiplied on single light particles and the wall chatters at 1-5 m/s (docs/robustness.md,
  // "The needle's virtual particles"). Such an anchor, and one without a frame, takes the
  // translation form.
  if (!extrapolates) {
    rotational = true;
  } else {
    // translation-only fallback: normalised inverse distances (a particle on X takes it all)
    rotational = false;
    double sum = 0.0;
    int on_point = -1;
    for (int a = 0; a < n; ++a) {
      const double d = (x[idx[a]] - X).norm();
      if (!(d > 1e-12)) { on_point = a; break; }
      w[a] = 1.0 / d;
      sum += w[a];
    }
    for (int a = 0; a < n; ++a) w[a] = on_point >= 0 ? (a == on_point ? 1.0 : 0.0) : w[a] / sum;
  }
  offset.setZero();
  offset = keep - evaluate(x);
}

Vec3 AffineAnchor::evaluate(const std::vector<Vec3>& x) const {
  Vec3 p = offset;
  for (int a = 0; a < count; ++a) p += w[a] * x[idx[a]];
  return p;
}

void AffineAnchor::add_reaction(std::vector<Vec3>& f, const std::vector<Vec3>&, const Vec3& F) const {
  for (int a = 0; a < count; ++a) f[idx[a]] -= w[a] * F;
}

Vec3 AffineAnchor::velocity(const std::vector<Vec3>& v) const {
  Vec3 u = Vec3::Zero();
  for (int a = 0; a < count; ++a) u += w[a] * v[idx[a]];
  return u;
}

}  // namespace ps
