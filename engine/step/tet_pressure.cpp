// Implicit nodal pressure (Model::tet_pressure, docs/model.md "Implicit pressure"): after the
// explicit integration, each node n with `pressure: implicit` has its volume constraint
//   C_n = V_n - V0_n,  compliance alpha_n = V0_n / kappa_n,
// solved as one backward-Euler (XPBD, Macklin et al. 2016) step per substep h:
//   (J W J^T + alpha / h^2) dlambda = -C(x) - alpha / h^2 lambda,   x += W J^T dlambda,
// J = dC/dx at the current positions on the right, the matrix prefactored at rest. For a linear
// constraint one solve is the exact implicit step, which is stable at any h: the pressure wave no
// longer limits the substep. The position change becomes velocity in adjust_velocities, like
// every other constraint. J^T dlambda is assembled per element: dC_n/dx_i = sum over the elements
// t around n of dV_t/dx_i / 4, so x_i moves by w_i sum_t dV_t/dx_i (sum of dlambda over t's nodes) / 4.
// No allocation: the scratch is sized at make_state.
#include "engine/model/tet_pressure.h"
#include "engine/step/stages.h"
#include "engine/step/tet_edges4.h"
#include "engine/util/multiversion.h"

namespace ps {

// x moves by W J^T dl (the correction dx before the mass weighting): for each element, the sum of
// dl over its implicit nodes (share) times the gradients of its volume, a quarter per node.
// Four elements per vector: each lane does the scalar form's operations in its order (Eigen's
// cross is a1 b2 - a2 b1 per component; share * 0.25 / 6 one product), and the four lanes are
// added to dx one after the other in element order, an element whose share is zero skipped as in
// the scalar form: the same bits as one element at a time.
PS_TARGET_CLONES("arch=x86-64-v4", "avx", "default")
void pressure_corrections(const int* tv, const int* trow, int ntp, const double* dl, const Vec3* x, Vec3* dx) {
  typedef double D4 __attribute__((vector_size(32)));
  auto share_of = [&](int j) {
    const int* row = trow + 4 * j;
    double share = 0.0;
    for (int i = 0; i < 4; ++i)
      if (const int r = row[i]; r >= 0) share += dl[r];
    return share;
  };
  int j = 0;
  for (; j + 4 <= ntp; j += 4) {
    double sh[4];
    #pragma GCC unroll 4
    for (int l = 0; l < 4; ++l) sh[l] = share_of(j + l);
    if (sh[0] == 0.0 && sh[1] == 0.0 && sh[2] == 0.0 && sh[3] == 0.0) continue;
    const int* v = tv + 4 * j;  // lane l's vertex i: v[4 l + i]
    D4 e[3][3];                 // e[k][r]: edge x_{k+1} - x_0, coordinate r
    tet_edges4(x, v, e);
    const D4 share = D4{sh[0], sh[1], sh[2], sh[3]} * (0.25 / 6.0);
    D4 g[3][3];  // g[k][r]: share x the gradient of the volume at vertex k + 1, coordinate r
    #pragma GCC unroll 16
    for (int k = 0; k < 3; ++k) {
      const D4* a = e[(k + 1) % 3];
      const D4* b = e[(k + 2) % 3];
      g[k][0] = share * (a[1] * b[2] - a[2] * b[1]);
      g[k][1] = share * (a[2] * b[0] - a[0] * b[2]);
      g[k][2] = share * (a[0] * b[1] - a[1] * b[0]);
    }
    #pragma GCC unroll 4
    for (int l = 0; l < 4; ++l) {
      if (sh[l] == 0.0) continue;
      const int* w = v + 4 * l;
      #pragma GCC unroll 3
      for (int r = 0; r < 3; ++r) {
        dx[w[1]][r] += g[0][r][l];
        dx[w[2]][r] += g[1][r][l];
        dx[w[3]][r] += g[2][r][l];
        dx[w[0]][r] -= (g[0][r][l] + g[1][r][l]) + g[2][r][l];
      }
    }
  }
  for (; j < ntp; ++j) {
    double share = share_of(j);
    if (share == 0.0) continue;
    const int* v = tv + 4 * j;
    share *= 0.25 / 6.0;  // a quarter per node, and dV/dx = (edge x edge) / 6
    const Vec3 e1 = x[v[1]] - x[v[0]], e2 = x[v[2]] - x[v[0]], e3 = x[v[3]] - x[v[0]];
    const Vec3 g1 = share * e2.cross(e3), g2 = share * e3.cross(e1), g3 = share * e1.cross(e2);
    dx[v[1]] += g1;
    dx[v[2]] += g2;
    dx[v[3]] += g3;
    dx[v[0]] -= g1 + g2 + g3;
  }
}

void project_tet_pressure(const Model& m, State& s, double dt) {
  const TetPressure& tp = m.tet_pressure;
  const int k = tp.size();
  if (k == 0) return;
  double* rhs = s.pressure_rhs.data();
  double* lambda = s.pressure_lambda.data();
  double* quarter = s.pressure_quarter.data();
  Vec3* dx = s.pressure_dx.data();
  Vec3* x = s.x.data();
  // the elements' particles and rows, copied contiguous at compile time (TetPressure::tet_v, tet_row)
  const int* tv = tp.tet_v.data();
  const int* trow = tp.tet_row.data();
  const int ntp = static_cast<int>(tp.tets.size());
  const double inv_h2 = 1.0 / (dt * dt);
  for (int r = 0; r < k; ++r) lambda[r] = 0.0;
  for (int it = 0; it < tp.iterations; ++it) {
    // C_n: volume shares of the implicit nodes at the current positions (four elements per vector)
    tet_quarters(tv, x, 0, ntp, quarter);
    for (int r = 0; r < k; ++r) rhs[r] = 0.0;
    for (int j = 0; j < ntp; ++j) {
      const int* row = trow + 4 * j;
      for (int i = 0; i < 4; ++i)
        if (const int r = row[i]; r >= 0) rhs[r] += quarter[j];
    }
    for (int r = 0; r < k; ++r) rhs[r] = -(rhs[r] - tp.vol0[r]) - tp.alpha[r] * inv_h2 * lambda[r];
    solve_tet_pressure(tp, rhs, s.pressure_work.data());  // rhs <- dlambda
    for (int r = 0; r < k; ++r) lambda[r] += rhs[r];
    // x += W J^T dlambda, J at the current positions
    for (int p : tp.particles) dx[p].setZero();
    pressure_corrections(tv, trow, ntp, rhs, x, dx);
    for (int p : tp.particles) {
      const double w = m.inv_mass[p];
      if (w == 0.0) continue;
      const uint8_t locked = m.locked_axes[p];
      for (int a = 0; a < 3; ++a)
        if (!(locked & (1u << a))) x[p][a] += w * dx[p][a];
    }
  }
}

}  // namespace ps
