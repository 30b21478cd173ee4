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

namespace ps {

void project_tet_pressure(const Model& m, State& s, double dt) {
  const TetPressure& tp = m.tet_pressure;
  const int k = tp.size();
  if (k == 0) return;
  double* rhs = s.pressure_rhs.data();
  double* lambda = s.pressure_lambda.data();
  Vec3* dx = s.pressure_dx.data();
  Vec3* x = s.x.data();
  // the elements' particles and rows, copied contiguous at compile time (TetPressure::tet_v, tet_row)
  const int* tv = tp.tet_v.data();
  const int* trow = tp.tet_row.data();
  const int ntp = static_cast<int>(tp.tets.size());
  const double inv_h2 = 1.0 / (dt * dt);
  for (int r = 0; r < k; ++r) lambda[r] = 0.0;
  for (int it = 0; it < tp.iterations; ++it) {
    // C_n: volume shares of the implicit nodes at the current positions
    for (int r = 0; r < k; ++r) rhs[r] = 0.0;
    for (int j = 0; j < ntp; ++j) {
      const int* v = tv + 4 * j;
      const int* row = trow + 4 * j;
      const Vec3 x0 = x[v[0]];
      const double quarter = (x[v[1]] - x0).dot((x[v[2]] - x0).cross(x[v[3]] - x0)) / 24.0;  // V_t / 4 [m^3]
      for (int i = 0; i < 4; ++i)
        if (const int r = row[i]; r >= 0) rhs[r] += quarter;
    }
    for (int r = 0; r < k; ++r) rhs[r] = -(rhs[r] - tp.vol0[r]) - tp.alpha[r] * inv_h2 * lambda[r];
    solve_tet_pressure(tp, rhs, s.pressure_work.data());  // rhs <- dlambda
    for (int r = 0; r < k; ++r) lambda[r] += rhs[r];
    // x += W J^T dlambda, J at the current positions
    for (int p : tp.particles) dx[p].setZero();
    for (int j = 0; j < ntp; ++j) {
      const int* v = tv + 4 * j;
      const int* row = trow + 4 * j;
      double share = 0.0;
      for (int i = 0; i < 4; ++i)
        if (const int r = row[i]; r >= 0) share += rhs[r];
      if (share == 0.0) continue;
      share *= 0.25 / 6.0;  // a quarter per node, and dV/dx = (edge x edge) / 6
      const Vec3 e1 = x[v[1]] - x[v[0]], e2 = x[v[2]] - x[v[0]], e3 = x[v[3]] - x[v[0]];
      const Vec3 g1 = share * e2.cross(e3), g2 = share * e3.cross(e1), g3 = share * e1.cross(e2);
      dx[v[1]] += g1;
      dx[v[2]] += g2;
      dx[v[3]] += g3;
      dx[v[0]] -= g1 + g2 + g3;
    }
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
