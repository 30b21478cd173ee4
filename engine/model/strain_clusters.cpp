#include "engine/model/strain_clusters.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "engine/model/material.h"
#include "engine/util/error.h"

namespace ps {

namespace {

// Variationally consistent integration (Chen, Hillman, Rüter 2013) of the clusters of one
// component. Exact equilibrium of a uniform stress sigma needs, for every particle i,
//   sum_c V_c g_ci = a_i,   a_i = dV/dx_i of the component's closed surface (0 inside),
// the discrete divergence theorem: then the strain forces -sum_c V_c sigma g_ci of a uniform
// stress are exactly the pressure-like surface forces sigma a_i, the patch test passes and a
// uniformly strained body stays uniform (with g = q = S^-1 d0 it fails next to the surface,
// where clusters are truncated). We add to each cluster's gradient weights a correction that is
// orthogonal to the affine motions of the cluster (sum_i D_ci = 0, sum_i D_ci d0_ci^T = 0: F of
// every affine motion is unchanged), of least norm: D_c = V_c (I - Pi_c) lambda|_c with lambda
// solving sum_c V_c^2 (I - Pi_c) lambda|_c = a - sum_c V_c q_c by conjugate gradients, one
// coordinate at a time. Returns the relative residual |a - sum_c V_c g_c| / |a| reached.
double consistent_weights(const StrainClusters& sc, int first_cluster, int last_cluster, const std::vector<double>& vol,
                          const std::vector<Vec3>& target, int n, std::vector<Vec3>& g) {
  // (I - Pi_c) y for y on the members of c: y - mean(y) - d0_i . sum_j q_j y_j
  auto apply = [&](const std::vector<double>& lam, std::vector<double>& out, int axis, bool want_delta) {
    std::fill(out.begin(), out.end(), 0.0);
    for (int c = first_cluster; c < last_cluster; ++c) {
      const int b = sc.start[c], e = sc.start[c + 1];
      double mean = 0.0;
      Vec3 qy = Vec3::Zero();
      for (int a = b; a < e; ++a) { mean += lam[sc.member[a]]; qy += sc.q[a] * lam[sc.member[a]]; }
      mean /= (e - b);
      for (int a = b; a < e; ++a) {
        const double d = lam[sc.member[a]] - mean - sc.d0[a].dot(qy);
        if (want_delta) g[a][axis] += vol[c] * d;
        else out[sc.member[a]] += vol[c] * vol[c] * d;
      }
    }
  };
  // The operator is only semi-definite (lambda affine on every cluster, e.g. a trilinear field
  // on a lattice, gives 0) and the target need not be exactly in its range (the surface
  // triangulation's corner weights), so CG runs on the Tikhonov-regularised K + eps I (SPD,
  // eps = 1e-9 of K's mean diagonal): the range part is solved, the rest is left as residual.
  std::vector<double> diag(n, 0.0);
  for (int c = first_cluster; c < last_cluster; ++c)
    for (int a = sc.start[c]; a < sc.start[c + 1]; ++a) diag[sc.member[a]] += vol[c] * vol[c];
  double eps = 0.0;
  int active = 0;
  for (double d : diag) if (d > 0.0) { eps += d; ++active; }
  eps = active ? 1e-9 * eps / active : 0.0;
  std::vector<double> rhs(n), lam(n), r(n), p(n), Ap(n);
  for (int axis = 0; axis < 3; ++axis) {
    for (int i = 0; i < n; ++i) rhs[i] = target[i][axis];
    for (int c = first_cluster; c < last_cluster; ++c)
      for (int a = sc.start[c]; a < sc.start[c + 1]; ++a) rhs[sc.member[a]] -= vol[c] * sc.q[a][axis];
    std::fill(lam.begin(), lam.end(), 0.0);
    r = rhs;
    p = r;
    double rr = 0.0;
    for (double v : r) rr += v * v;
    const double r0 = rr;
    for (int it = 0; it < 5000 && rr > 1e-30 * r0 && rr > 0.0; ++it) {
      apply(p, Ap, axis, false);
      double pAp = 0.0;
      for (int i = 0; i < n; ++i) { Ap[i] += eps * p[i]; pAp += p[i] * Ap[i]; }
      if (!(pAp > 0.0)) break;
      const double alpha = rr / pAp;
      double rr_new = 0.0;
      for (int i = 0; i < n; ++i) { lam[i] += alpha * p[i]; r[i] -= alpha * Ap[i]; rr_new += r[i] * r[i]; }
      const double beta = rr_new / rr;
      rr = rr_new;
      for (int i = 0; i < n; ++i) p[i] = r[i] + beta * p[i];
    }
    apply(lam, Ap, axis, true);  // g += D
  }
  // D = g - q once more through (I - Pi_c): lambda's components along the null space can be
  // large (the regularisation lets them grow where the target is out of range), and round-off
  // of their projection would leave D a part with a non-zero sum (momentum) or an affine part
  for (int c = first_cluster; c < last_cluster; ++c) {
    const int b = sc.start[c], e = sc.start[c + 1];
    Vec3 mean = Vec3::Zero();
    Mat3 qd = Mat3::Zero();  // sum_j q_j D_j^T
    for (int a = b; a < e; ++a) { mean += g[a] - sc.q[a]; qd += sc.q[a] * (g[a] - sc.q[a]).transpose(); }
    mean /= (e - b);
    for (int a = b; a < e; ++a) g[a] = sc.q[a] + ((g[a] - sc.q[a]) - mean - qd.transpose() * sc.d0[a]);
  }
  // the residual actually reached
  std::vector<Vec3> sum(n, Vec3::Zero());
  for (int c = first_cluster; c < last_cluster; ++c)
    for (int a = sc.start[c]; a < sc.start[c + 1]; ++a) sum[sc.member[a]] += vol[c] * g[a];
  double num = 0.0, den = 0.0;
  for (int i = 0; i < n; ++i) { num += (target[i] - sum[i]).squaredNorm(); den += target[i].squaredNorm(); }
  return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

}  // namespace

std::vector<std::string> build_strain_clusters(Model& m, const std::vector<StrainParticle>& mat) {
  std::vector<std::string> warnings;
  StrainClusters& sc = m.strain;
  sc = StrainClusters{};
  const int n = m.particle_count();
  sc.start.push_back(0);
  std::vector<int> members;
  std::vector<double> vol;  // [nc] V_c [m^3]
  for (size_t ci = 0; ci < m.components.size(); ++ci) {
    const Component& comp = m.components[ci];
    const int first = sc.count();
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      if (!m.shape_memory[p] || !(mat[p].mu > 0.0)) continue;
      // members of the same component only: the consistency condition is per closed surface
      // (links to other components are carried by the shape-memory term)
      members.assign(1, p);
      for (int a = m.nbr_start[p]; a < m.nbr_start[p + 1]; ++a)
        if (m.component_of[m.nbr[a]] == static_cast<int>(ci)) members.push_back(m.nbr[a]);
      Vec3 c0 = Vec3::Zero();
      for (int i : members) c0 += m.rest_pos[i];
      c0 /= static_cast<double>(members.size());
      Mat3 S = Mat3::Zero();
      for (int i : members) S += (m.rest_pos[i] - c0) * (m.rest_pos[i] - c0).transpose();
      const Eigen::SelfAdjointEigenSolver<Mat3> eig(S, Eigen::EigenvaluesOnly);
      if (!(eig.eigenvalues()[0] > kClusterConditionMin * eig.eigenvalues()[2]))
        throw CompileError("particle " + std::to_string(p) + " (component '" + comp.name +
                           "'): its neighbours are flat or collinear, the strain model needs a neighbourhood that "
                           "spans 3-D (use fill: volumetric or model: paper)");
      const Mat3 Sinv = S.inverse();
      for (int i : members) {
        sc.member.push_back(i);
        sc.d0.push_back(m.rest_pos[i] - c0);
        sc.q.push_back(Sinv * (m.rest_pos[i] - c0));
      }
      sc.centre.push_back(p);
      sc.start.push_back(static_cast<int>(sc.member.size()));
      vol.push_back(mat[p].volume);
      sc.mu2v.push_back(2.0 * mat[p].mu * mat[p].volume);
      sc.k_v.push_back(mat[p].lambda * mat[p].volume);
      sc.k_r.push_back(kStrainResidualFactor * 6.0 * mat[p].mu * mat[p].volume / S.trace());
    }
    const int last = sc.count();
    if (last == first) continue;
    // consistent gradient weights: needs the component's closed surface
    std::vector<Vec3> target(n, Vec3::Zero());
    if (comp.surface >= 0) {
      for (const auto& f : m.surfaces[comp.surface].faces)
        for (int k = 0; k < 3; ++k)
          target[f[k]] += m.rest_pos[f[(k + 1) % 3]].cross(m.rest_pos[f[(k + 2) % 3]]) / 6.0;
    }
    // V_c scaled so that sum_c V_c is the volume the surface encloses (the moment condition
    // sum_i a_i x_i^T = V I that the consistency needs)
    double vsum = 0.0, venc = 0.0;
    for (int c = first; c < last; ++c) vsum += vol[c];
    for (int i = 0; i < n; ++i) venc += target[i].dot(m.rest_pos[i]) / 3.0;
    if (venc > 0.0)
      for (int c = first; c < last; ++c) vol[c] *= venc / vsum;
    sc.g.resize(sc.q.size());
    for (int a = sc.start[first]; a < sc.start[last]; ++a) sc.g[a] = sc.q[a];
    const double res = consistent_weights(sc, first, last, vol, target, n, sc.g);
    if (res > kClusterConsistencyWarn)
      warnings.push_back("component '" + comp.name + "': strain clusters pass the patch test only to " +
                         std::to_string(res) + " (relative), a uniform strain will not stay exactly uniform");
  }
  return warnings;
}

}  // namespace ps
