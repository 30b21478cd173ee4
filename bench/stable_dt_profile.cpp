// `prostatesim_bench --dt-profile FILE`: what sets the stable substep of a scenario file.
// The compiler's estimate is 2/sqrt(lambda_max(M^-1 K)) of the undamped linearisation at rest
// (compile_time_step.cpp estimate_stable_dt, power iteration). This mode runs the same power iteration
// longer, keeps the eigenvector and prints:
//   - the particles that carry the top mode (largest |v|), with component, tag bits, surface
//     flag, mass, k_e, neighbours, triplets and beta triplets, and the share of the mode held by
//     each component (sum |v|^2 over its particles);
//   - the limit each component alone would set (power iteration on its own free coordinates,
//     the others held at rest): which term is stiffest;
//   - the triplet statistics behind the shape-memory stiffness: quality |n|/longest^2 and the
//     amplification |b| longest/|n| of the normal term (how far a vertex's motion moves P*).
// Tools (needle coupling springs) are not part of the compiled model; their own bound is in
// engine/tools/needle/needle_coupling.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <vector>

#include "bench/bench_modes.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/stages.h"

namespace ps::bench {

namespace {

// lambda_max(M^-1 K) restricted to the free coordinates where mask[p] is set; v = eigenvector
double power_iteration(const Model& m, const std::vector<uint8_t>& mask, int iters, std::vector<Vec3>& v) {
  const int n = m.particle_count();
  State s = make_state(m);
  std::vector<Vec3> w(n);
  v.assign(n, Vec3::Zero());
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  auto free_axis = [&](int p, int a) {
    return mask[p] && m.inv_mass[p] > 0.0 && !(m.locked_axes[p] & (1u << a));
  };
  for (int p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) v[p][a] = free_axis(p, a) ? U(rng) : 0.0;
  double lambda = 0.0;
  for (int it = 0; it < iters; ++it) {
    double norm = 0.0;
    for (const Vec3& x : v) norm += x.squaredNorm();
    norm = std::sqrt(norm);
    if (!(norm > 0.0)) return 0.0;
    const double eps = 1e-10 / norm;
    for (int p = 0; p < n; ++p) { s.x[p] = m.rest_pos[p] + eps * v[p]; s.f[p].setZero(); }
    add_shape_memory_forces(m, s);
    if (m.strain.count() > 0) add_strain_memory_forces(m, s, 50);
    if (m.tets.count() > 0) add_tet_elastic_forces(m, s);
    if (m.shells.triangle_count() > 0) add_shell_elastic_forces(m, s);
    double wn = 0.0;
    for (int p = 0; p < n; ++p) {
      for (int a = 0; a < 3; ++a) w[p][a] = free_axis(p, a) ? -s.f[p][a] * m.inv_mass[p] / eps : 0.0;
      wn += w[p].squaredNorm();
    }
    wn = std::sqrt(wn);
    lambda = wn / norm;
    if (!(wn > 0.0)) return 0.0;
    for (int p = 0; p < n; ++p) v[p] = w[p] / wn;
  }
  return lambda;
}

std::string tags_of(const Model& m, int p) {
  std::string t;
  if (m.particle_tags.empty()) return "-";
  for (size_t i = 0; i < m.tag_names.size(); ++i)
    if (m.particle_tags[p] & (uint64_t{1} << i)) t += (t.empty() ? "" : ",") + m.tag_names[i];
  return t.empty() ? "-" : t;
}

}  // namespace

int stable_dt_profile(const std::string& file) {
  const ScenarioSpec spec = parse_scenario_file(file);
  auto mp = compile_scenario(spec);
  const Model& m = *mp;
  const int n = m.particle_count();
  std::printf("%s: %d particles, estimate %.4g ms, %d substeps of %.4g ms per %.3g ms tick\n", file.c_str(), n,
              m.stable_dt_estimate * 1e3, m.substeps, m.dt / m.substeps * 1e3, m.dt * 1e3);
  std::vector<Vec3> v;
  const double lam = power_iteration(m, std::vector<uint8_t>(n, 1), 300, v);
  std::printf("whole scene: lambda_max %.4g 1/s^2, limit 2/sqrt(lambda) = %.4g ms\n", lam, 2e3 / std::sqrt(lam));
  // mode shares per component
  std::printf("top mode share by component:");
  for (size_t c = 0; c < m.components.size(); ++c) {
    double e = 0;
    for (int p = 0; p < n; ++p)
      if (m.component_of[p] == static_cast<int>(c)) e += v[p].squaredNorm();
    std::printf(" %s %.3f", m.components[c].name.c_str(), e);
  }
  std::printf("\n");
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::partial_sort(order.begin(), order.begin() + 8, order.end(),
                    [&](int a, int b) { return v[a].squaredNorm() > v[b].squaredNorm(); });
  std::printf("  particle  |v|^2   component  tags  surface  mass[g]  k_e[N/m]  nbrs  triplets  beta  k_e/m[1/s^2]\n");
  for (int r = 0; r < 8; ++r) {
    const int p = order[r];
    std::printf("  %6d  %.3f  %-10s %-8s %d  %.4f  %8.1f  %2d  %3d  %3d  %.3g\n", p, v[p].squaredNorm(),
                m.components[m.component_of[p]].name.c_str(), tags_of(m, p).c_str(), m.on_surface[p],
                m.mass[p] * 1e3, m.k_e[p], m.nbr_start[p + 1] - m.nbr_start[p], m.triplet_count[p],
                m.beta_start[p + 1] - m.beta_start[p], m.k_e[p] * m.inv_mass[p]);
  }
  // each component alone
  for (size_t c = 0; c < m.components.size(); ++c) {
    std::vector<uint8_t> mask(n, 0);
    double kmax = 0, kmean = 0, mmin = 1e300;
    int cnt = 0;
    for (int p = 0; p < n; ++p)
      if (m.component_of[p] == static_cast<int>(c)) {
        mask[p] = 1;
        if (m.inv_mass[p] > 0) {  // element models (tet, shell) have k_e = 0: counted all the same
          kmax = std::max(kmax, m.k_e[p] * m.inv_mass[p]);
          kmean += m.k_e[p] * m.inv_mass[p];
          mmin = std::min(mmin, m.mass[p]);
          ++cnt;
        }
      }
    if (cnt == 0) continue;
    std::vector<Vec3> vc;
    const double lc = power_iteration(m, mask, 200, vc);
    std::printf("component %-10s alone: limit %.4g ms (lambda %.3g); max k_e/m %.3g, mean %.3g 1/s^2 "
                "(a lone spring k_e/m would allow %.3g ms), lightest particle %.3g g\n",
                m.components[c].name.c_str(), 2e3 / std::sqrt(lc), lc, kmax, kmean / cnt, 2e3 / std::sqrt(kmax),
                mmin * 1e3);
  }
  // triplet statistics
  std::vector<double> quality, amp;
  double beta_per = 0;
  int sm = 0;
  for (int p = 0; p < n; ++p) {
    if (!m.shape_memory[p]) continue;
    ++sm;
    beta_per += m.beta_start[p + 1] - m.beta_start[p];
    for (int t = m.beta_start[p]; t < m.beta_start[p + 1]; ++t) {
      const BetaTriplet& b = m.beta[t];
      const Vec3 e1 = m.rest_pos[b.j] - m.rest_pos[b.i], e2 = m.rest_pos[b.k] - m.rest_pos[b.i];
      const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm()});
      const double nn = e1.cross(e2).norm();
      quality.push_back(nn / longest2);
      // |b_t| here is beta_t / m_p; the triplet's own amplification is m_p |b_t| longest / |n|
      amp.push_back(std::abs(b.b) * m.triplet_count[p] * std::sqrt(longest2) / nn);
    }
  }
  auto pct = [](std::vector<double> x, double q) {
    if (x.empty()) return 0.0;
    std::sort(x.begin(), x.end());
    return x[std::min(x.size() - 1, static_cast<size_t>(q * (x.size() - 1)))];
  };
  std::printf("beta triplets: %.1f per shape-memory particle; quality |n|/longest^2 p1 %.3f p10 %.3f p50 %.3f; "
              "normal-term amplification |beta| longest/|n| p50 %.2f p90 %.2f p99 %.2f max %.2f\n",
              beta_per / std::max(sm, 1), pct(quality, 0.01), pct(quality, 0.1), pct(quality, 0.5), pct(amp, 0.5),
              pct(amp, 0.9), pct(amp, 0.99), pct(amp, 1.0));
  return 0;
}

}  // namespace ps::bench
