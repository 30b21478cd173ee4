// Verbatim copy of engine/step/shape_memory.cpp add_shape_memory_forces() before the
// performance work (git 135992e), renamed. Used only by the benchmarks: the speed-up of the
// optimised stage is measured against it in the same run, and `--verify` compares forces.
#include <cmath>

#include "bench/bench_modes.h"

namespace ps::bench {

void reference_add_shape_memory_forces(const Model& m, State& s) {
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
      if (len2 > 0.0) target += (bt.b / std::sqrt(len2)) * nrm;
    }
    s.attractor[p] = target;
    const Vec3 F = m.k_e[p] * (target - x[p]);
    f[p] += F;
    for (int a = ns; a < ne; ++a) f[m.nbr[a]] -= m.nbr_w[a] * F;
    if (!gradient) continue;
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

}  // namespace ps::bench
