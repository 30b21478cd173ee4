// Compile-time half of the implicit nodal pressure (engine/model/tet_pressure.h): which nodes,
// elements and particles take part, and the sparse LDL^T factor of the constraint system at rest.
// Eigen's SimplicialLDLT orders (AMD) and factors; its factor is copied into plain arrays so the
// step's triangular solves neither allocate nor depend on Eigen's solve expressions, and a solve
// of a fixed vector checks the copy against Eigen's own.
#include "engine/model/tet_pressure.h"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstdio>

#include "engine/util/error.h"

namespace ps {

namespace {

// gradients of the volume of element t at positions x with respect to its four vertices [m^2]
void volume_gradients(const TetElements& te, const std::vector<Vec3>& x, int t, Vec3 g[4]) {
  const int* v = &te.v[4 * t];
  const Vec3 e1 = x[v[1]] - x[v[0]], e2 = x[v[2]] - x[v[0]], e3 = x[v[3]] - x[v[0]];
  g[1] = e2.cross(e3) / 6.0;
  g[2] = e3.cross(e1) / 6.0;
  g[3] = e1.cross(e2) / 6.0;
  g[0] = -(g[1] + g[2] + g[3]);
}

}  // namespace

std::string build_tet_pressure(Model& m, int iterations) {
  TetPressure& tp = m.tet_pressure;
  tp = TetPressure{};
  const TetElements& te = m.tets;
  const int nn = static_cast<int>(te.nodes.size());
  tp.slot_row.assign(nn, -1);
  for (int a = 0; a < nn; ++a) {
    if (te.node_implicit.empty() || !te.node_implicit[a]) continue;
    tp.slot_row[a] = static_cast<int>(tp.row_slot.size());
    tp.row_slot.push_back(a);
    const double v0 = 1.0 / te.node_inv_vol0[a];
    tp.vol0.push_back(v0);
    tp.alpha.push_back(v0 / te.node_kappa[a]);
  }
  const int k = tp.size();
  if (k == 0) {
    tp.slot_row.clear();
    return {};
  }
  tp.h = m.dt / m.substeps;
  tp.iterations = iterations;
  const int n = m.particle_count();
  auto row_of = [&](int p) { return tp.slot_row[te.node_slot[p]]; };
  std::vector<uint8_t> in_support(n, 0);
  for (int t = 0; t < te.count(); ++t) {
    const int* v = &te.v[4 * t];
    bool any = false;
    for (int i = 0; i < 4; ++i) any |= row_of(v[i]) >= 0;
    if (!any) continue;
    tp.tets.push_back(t);
    for (int i = 0; i < 4; ++i) {
      in_support[v[i]] = 1;
      tp.tet_v.push_back(v[i]);
      tp.tet_row.push_back(row_of(v[i]));
    }
  }
  std::vector<int> local(n, -1);
  for (int p = 0; p < n; ++p)
    if (in_support[p]) {
      local[p] = static_cast<int>(tp.particles.size());
      tp.particles.push_back(p);
    }
  // dC_r/dx_p at rest, per support particle: a short list of (row, gradient)
  std::vector<std::vector<std::pair<int, Vec3>>> grad(tp.particles.size());
  for (int t : tp.tets) {
    Vec3 g[4];
    volume_gradients(te, m.rest_pos, t, g);
    const int* v = &te.v[4 * t];
    for (int j = 0; j < 4; ++j) {  // node j's constraint gets a quarter of the element's volume
      const int r = row_of(v[j]);
      if (r < 0) continue;
      for (int i = 0; i < 4; ++i) {
        auto& list = grad[local[v[i]]];
        auto it = list.begin();
        while (it != list.end() && it->first != r) ++it;
        if (it == list.end()) list.emplace_back(r, 0.25 * g[i]);
        else it->second += 0.25 * g[i];
      }
    }
  }
  // A = J W J^T + diag(alpha / h^2): W per axis, 0 on fixed axes and for kinematic particles
  std::vector<Eigen::Triplet<double>> entries;
  for (size_t q = 0; q < tp.particles.size(); ++q) {
    const int p = tp.particles[q];
    Vec3 w = Vec3::Constant(m.inv_mass[p]);
    for (int a = 0; a < 3; ++a)
      if (m.locked_axes[p] & (1u << a)) w[a] = 0.0;
    if (w.isZero()) continue;
    for (const auto& [r, gr] : grad[q])
      for (const auto& [c, gc] : grad[q]) entries.emplace_back(r, c, gr.cwiseProduct(w).dot(gc));
  }
  const double inv_h2 = 1.0 / (tp.h * tp.h);
  for (int r = 0; r < k; ++r) entries.emplace_back(r, r, tp.alpha[r] * inv_h2);
  Eigen::SparseMatrix<double> A(k, k);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(A);
  if (ldlt.info() != Eigen::Success)
    throw CompileError("implicit pressure: the factorisation of the constraint system failed (" + std::to_string(k) +
                       " nodes); check the tet materials' young_kpa and poisson");
  const auto& idx = ldlt.permutationP().indices();
  tp.perm.assign(idx.data(), idx.data() + k);
  const Eigen::SparseMatrix<double>& L = ldlt.matrixL().nestedExpression();
  tp.l_start.assign(1, 0);
  for (int c = 0; c < k; ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, c); it; ++it)
      if (it.row() > c) {
        tp.l_row.push_back(static_cast<int>(it.row()));
        tp.l_val.push_back(it.value());
      }
    tp.l_start.push_back(static_cast<int>(tp.l_row.size()));
  }
  const Eigen::VectorXd D = ldlt.vectorD();
  tp.d.assign(D.data(), D.data() + k);
  // the copied factor must solve like Eigen's
  Eigen::VectorXd b(k);
  for (int r = 0; r < k; ++r) b[r] = std::sin(1.0 + r) * A.coeff(r, r);
  const Eigen::VectorXd want = ldlt.solve(b);
  std::vector<double> mine(b.data(), b.data() + k), work(k);
  solve_tet_pressure(tp, mine.data(), work.data());
  double err = 0.0, scale = 0.0;
  for (int r = 0; r < k; ++r) {
    err = std::max(err, std::abs(mine[r] - want[r]));
    scale = std::max(scale, std::abs(want[r]));
  }
  if (!(err <= 1e-9 * scale))
    throw CompileError("implicit pressure: the copied factor does not reproduce the solve (error " + std::to_string(err / scale) + ")");
  char note[200];
  std::snprintf(note, sizeof note,
                "implicit pressure: %d nodes, %zu elements, factor %zu entries, substep %.4g ms, %d solve(s) per substep",
                k, tp.tets.size(), tp.l_val.size() + k, tp.h * 1e3, tp.iterations);
  return note;
}

void solve_tet_pressure(const TetPressure& tp, double* b, double* y) {
  const int k = tp.size();
  const int* perm = tp.perm.data();
  const int* start = tp.l_start.data();
  const int* row = tp.l_row.data();
  const double* val = tp.l_val.data();
  for (int i = 0; i < k; ++i) y[perm[i]] = b[i];  // y = P b
  for (int c = 0; c < k; ++c) {                   // L y' = y
    const double yc = y[c];
    for (int e = start[c]; e < start[c + 1]; ++e) y[row[e]] -= val[e] * yc;
  }
  for (int c = 0; c < k; ++c) y[c] /= tp.d[c];    // D
  // L^T: each column's dot product in four running sums (in one sum every subtraction waits for
  // the one before: a chain as long as the factor, 16 140 entries in the default anatomy)
  for (int c = k - 1; c >= 0; --c) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int e = start[c];
    const int end = start[c + 1];
    for (; e + 4 <= end; e += 4) {
      s0 += val[e] * y[row[e]];
      s1 += val[e + 1] * y[row[e + 1]];
      s2 += val[e + 2] * y[row[e + 2]];
      s3 += val[e + 3] * y[row[e + 3]];
    }
    for (; e < end; ++e) s0 += val[e] * y[row[e]];
    y[c] -= (s0 + s1) + (s2 + s3);
  }
  for (int i = 0; i < k; ++i) b[i] = y[perm[i]];  // x = P^-1 y
}

}  // namespace ps
