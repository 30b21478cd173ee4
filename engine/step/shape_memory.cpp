// Shape-memory force (paper §3.2.1-3.2.3). For each elastic particle p:
//   P* = sum_j w_pj x_j + sum_t b_t n_t/|n_t|,   F* = k_e (P* - x_p),
// and -w_pj F* goes to each neighbour j ("redistributed ... proportional to the linear
// coefficient"), so internal forces sum to zero. For the linear part this is exactly the
// gradient of the energy 1/2 k_e |P* - P|^2.
//
// The beta terms make P* nonlinear in the neighbours. Redistributing only by the linear
// coefficients (the paper's literal rule, Redistribution::Linear) leaves a non-conservative
// residual: a stiff cube on a fixed base then grows an oscillation at any time step (measured:
// blow-up at t = 0.037 s for k_e = 1e6 N/m with dt from 5e-7 s down to 1.25e-7 s). The default,
// Redistribution::Gradient, also hands each triplet vertex its share -(dP*/dx_q)^T F* of the
// normal's derivative: the force is then exactly -grad of sum 1/2 k_e |P* - P|^2, conserves
// linear and angular momentum, and is stable below the explicit limit.

#include "engine/step/stages.h"

namespace ps {

void add_shape_memory_forces(const Model& m, State& s) {
  const int n = m.particle_count();
  const Vec3* x = s.x.data();
  Vec3* f = s.f.data();
  const bool gradient = m.redistribution == Redistribution::Gradient;
  for (int p = 0; p < n; ++p) {
    if (!m.shape_memory[p]) continue;
    Vec3 target = Vec3::Zero();
    const int ns = m.nbr_start[p], ne = m.nbr_start[p + 1];
    const int bs = m.beta_start[p], be = m.beta_start[p + 1];
    for (int a = ns; a < ne; ++a) target += m.nbr_w[a] * x[m.nbr[a]];
    for (int t = bs; t < be; ++t) {
      const BetaTriplet& bt = m.beta[t];
      const Vec3 nrm = (x[bt.j] - x[bt.i]).cross(x[bt.k] - x[bt.i]);
      const double len2 = nrm.squaredNorm();
      // a triangle crushed flat has no normal; its offset term is dropped for this step
      if (len2 > 0.0) target += (bt.b / std::sqrt(len2)) * nrm;
    }
    s.attractor[p] = target;
    const Vec3 F = m.k_e[p] * (target - x[p]);
    f[p] += F;
    for (int a = ns; a < ne; ++a) f[m.nbr[a]] -= m.nbr_w[a] * F;
    if (!gradient) continue;
    // d(b n/|n|)/dx_q transposed applied to F: with F_perp = F - (n.F) n / |n|^2,
    //   f_j -= b/|n| e_k x F_perp,  f_k += b/|n| e_j x F_perp,  f_i += b/|n| (e_k - e_j) x F_perp
    for (int t = bs; t < be; ++t) {
      const BetaTriplet& bt = m.beta[t];
      const Vec3 ej = x[bt.j] - x[bt.i], ek = x[bt.k] - x[bt.i];
      const Vec3 nrm = ej.cross(ek);
      const double len2 = nrm.squaredNorm();
      if (!(len2 > 0.0)) continue;
      const double inv_len = 1.0 / std::sqrt(len2);
      const Vec3 Fp = (bt.b * inv_len) * (F - (nrm.dot(F) / len2) * nrm);
      const Vec3 fj = ek.cross(Fp), fk = ej.cross(Fp);
      f[bt.j] -= fj;
      f[bt.k] += fk;
      f[bt.i] += fj - fk;
    }
  }
}

}  // namespace ps
