// Strain-memory force (docs/model.md "Strain memory"): per-particle-cluster meshless
// co-rotational elasticity, the shape matching of Müller et al. 2005 with its energy split into
// an affine part that sees the strain and a non-affine rest. For cluster c (Model::strain), with
// g the consistent gradient weights and q = S^-1 d0 the least-squares ones (Sum g = Sum q = 0):
//   F = sum_i (x_i - x_c) g_i^T,  R = polar rotation of F,  J = det F
//   F_ls = sum_i (x_i - x_c) q_i^T,  r_i = x_i - x_c - F_ls d0_i
//   E_c = mu2v/2 |F - R|^2 + k_v/2 (J - 1)^2 + k_r/2 sum_i |r_i|^2
//   f_i = -P g_i - k_r r_i,   P = mu2v (F - R) + k_v (J - 1) cof F      (first Piola stress x V)
// This is exactly -dE_c/dx_i: dF/dx_i = I (x) g_i because sum_i g_i = 0 (the centroid drops
// out); r is the orthogonal projection of the positions onto the non-affine motions, so its
// energy's gradient is r itself; and R enters only through |F - R|^2, at its minimum over
// rotations (envelope theorem: no dR/dx term). sum_i f_i = 0: momentum is conserved; the energy
// is invariant under rotations, so angular momentum is too (to the rotation's tolerance).
//
// The paper's attractor P* reproduces any affine map of a symmetric neighbourhood, so the
// shape-memory force alone leaves the interior blind to uniform strain; this term is what gives
// the interior its stiffness (docs/model.md).
//
// R: after Müller, Bender, Chentanez, Macklin 2016, "A robust method to extract the rotational
// part of deformations": R <- exp([omega]) R, warm started from the previous substep's rotation
// (State::strain_rot), stopped when |omega| < 1e-9 rad or after kPolarIterations; omega is the
// Newton step where it is safe, their step otherwise (extract_rotation). It always returns a
// proper rotation, also for inverted (J < 0) or collapsed clusters (F = 0 leaves R unchanged),
// and it maximises tr(R^T F), so it is the polar rotation whenever det F > 0. Deterministic:
// fixed order, fixed iteration rule, no allocation.
#include <cmath>

#include "engine/step/stages.h"

namespace ps {

namespace {

constexpr int kPolarIterations = 8;       // cap; warm-started, ~2 are used on average (cube11s)
constexpr double kPolarTolerance = 1e-9;  // |omega| [rad] below which R is converged

// Rotation maximising tr(R^T F), updated in place from the warm start q; returns R.
// Müller et al. 2016 iterate R <- exp([w]) R with w = g / |tr B|, g = sum_k R_k x F_k, B = F R^T:
// a gradient step whose length assumes the Hessian tr(B) I; the true Hessian is
// H = tr(B) I - sym(B) (2 I near the answer), so their step is 2/3 of Newton's and each iteration
// only divides the error by 3 (measured: the 1e-9 tolerance then took ~8 iterations per cluster
// and substep). We take the Newton step w = H^-1 g when H is positive definite (quadratic
// convergence: 1-2 iterations when warm-started) and Müller's step otherwise (inverted or
// strongly sheared clusters), which is robust. exp([w]) as a quaternion, with the Taylor series
// of cos(w/2) and sin(w/2)/w below 1e-3 rad (exact to round-off there) so no sin/cos is called in
// the common case.
inline Mat3 extract_rotation(const Mat3& F, Quat& q, int max_iter) {
  Mat3 R = q.toRotationMatrix();
  for (int it = 0; it < max_iter; ++it) {
    const Vec3 g = R.col(0).cross(F.col(0)) + R.col(1).cross(F.col(1)) + R.col(2).cross(F.col(2));
    const Mat3 B = F * R.transpose();
    const double tr = B.trace();
    const Mat3 H = tr * Mat3::Identity() - 0.5 * (B + B.transpose());
    // positive definite by leading minors (Sylvester)
    const double m1 = H(0, 0), m2 = H(0, 0) * H(1, 1) - H(0, 1) * H(1, 0), m3 = H.determinant();
    Vec3 omega;
    if (m1 > 0.0 && m2 > 0.0 && m3 > 1e-12 * m1 * m1 * m1) omega = H.inverse() * g;
    else omega = g / (std::abs(tr) + 1e-9);
    const double w2 = omega.squaredNorm();
    if (!(w2 >= kPolarTolerance * kPolarTolerance)) break;  // converged (or NaN: leave R; the check reports it)
    double c, sw;  // cos(w/2), sin(w/2)/w
    if (w2 < 1e-6) {
      c = 1.0 - w2 / 8.0 + w2 * w2 / 384.0;
      sw = 0.5 - w2 / 48.0 + w2 * w2 / 3840.0;
    } else {
      const double w = std::sqrt(w2);
      c = std::cos(0.5 * w);
      sw = std::sin(0.5 * w) / w;
    }
    q = Quat(c, sw * omega.x(), sw * omega.y(), sw * omega.z()) * q;
    q.normalize();
    R = q.toRotationMatrix();
  }
  return R;
}

// Centroid xc of cluster c, its deformation gradient F = sum (x_i - xc) g_i^T (consistent
// weights) and Fls = sum (x_i - xc) q_i^T, the least-squares affine fit whose misfit is the non-affine residual.
void cluster_deformation(const StrainClusters& sc, const State& s, int c, Vec3& xc, Mat3& F, Mat3& Fls) {
  const int b = sc.start[c], e = sc.start[c + 1];
  xc = Vec3::Zero();
  for (int a = b; a < e; ++a) xc += s.x[sc.member[a]];
  xc /= static_cast<double>(e - b);
  F = Mat3::Zero();
  Fls = Mat3::Zero();
  for (int a = b; a < e; ++a) {
    const Vec3 d = s.x[sc.member[a]] - xc;
    F.noalias() += d * sc.g[a].transpose();
    Fls.noalias() += d * sc.q[a].transpose();
  }
}

}  // namespace

void add_strain_memory_forces(const Model& m, State& s, int polar_iterations) {
  const StrainClusters& sc = m.strain;
  const int nc = sc.count();
  const int iters = polar_iterations > 0 ? polar_iterations : kPolarIterations;
  for (int c = 0; c < nc; ++c) {
    const int b = sc.start[c], e = sc.start[c + 1];
    Vec3 xc;
    Mat3 F, Fls;
    cluster_deformation(sc, s, c, xc, F, Fls);
    const Mat3 R = extract_rotation(F, s.strain_rot[c], iters);
    Mat3 P = sc.mu2v[c] * (F - R);
    if (sc.k_v[c] != 0.0) {
      Mat3 cof;  // cofactor matrix of F: dJ/dF, defined also where F is singular
      cof.col(0) = F.col(1).cross(F.col(2));
      cof.col(1) = F.col(2).cross(F.col(0));
      cof.col(2) = F.col(0).cross(F.col(1));
      const double J = F.col(0).dot(cof.col(0));
      P += sc.k_v[c] * (J - 1.0) * cof;
    }
    const double kr = sc.k_r[c];
    for (int a = b; a < e; ++a) {
      const int i = sc.member[a];
      const Vec3 r = (s.x[i] - xc) - Fls * sc.d0[a];
      s.f[i] -= P * sc.g[a] + kr * r;
    }
  }
}

double strain_memory_energy(const Model& m, const State& s) {
  const StrainClusters& sc = m.strain;
  double energy = 0.0;
  for (int c = 0; c < sc.count(); ++c) {
    const int b = sc.start[c], e = sc.start[c + 1];
    Vec3 xc;
    Mat3 F, Fls;
    cluster_deformation(sc, s, c, xc, F, Fls);
    Quat q = s.strain_rot[c];
    const Mat3 R = extract_rotation(F, q, 100);  // converged: the energy at its optimal rotation
    const double J = F.determinant();
    double res = 0.0;
    for (int a = b; a < e; ++a) res += ((s.x[sc.member[a]] - xc) - Fls * sc.d0[a]).squaredNorm();
    energy += 0.5 * sc.mu2v[c] * (F - R).squaredNorm() + 0.5 * sc.k_v[c] * (J - 1.0) * (J - 1.0) + 0.5 * sc.k_r[c] * res;
  }
  return energy;
}

}  // namespace ps
