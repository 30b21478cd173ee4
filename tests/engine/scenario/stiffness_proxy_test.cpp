// The stiffness proxy (engine/scenario/compile.h stiffness_proxy) of the tet model against the
// stiffness itself: for each particle, its own 3x3 block H_pp of the elastic Hessian at rest, by
// central differences of the tet force, bounds the proxy, lambda_max(H_pp) <= d_p <= trace(H_pp).
// (Shear: the block is V0 mu |g|^2 times the identity, the J term adds nothing to it; nodal
// pressure: a sum of rank-one blocks kappa_n / V0_n a a^T, a = dV_n/dx_p, whose trace the proxy
// takes.) The element bound, each element's volume counted as its own (V0 kappa |g|^2), reads
// about 8x the nodal term in the default anatomy's fat: above the trace, so sizing inertia on it
// would put inertia on the fat that it does not need (docs/model.md "Multi-rate elements").
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "engine/scenario/compile.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

std::string block_yaml(double poisson) {
  return "name: proxy_block\ntime: {dt_ms: 1, substeps: 1, duration_s: 1}\nmaterials:\n"
         "  soft: {young_kpa: 3, density_kg_m3: 940, model: tet, poisson: " + std::to_string(poisson) +
         "}\ncomponents:\n  - {name: b, material: soft, spacing_mm: 10, box: {min_mm: [0, 0, 0], max_mm: [60, 60, 50]}}\n"
         "constraints:\n  - fix: {component: b, region: {half_space: {point_mm: [0, 0, 1], normal: [0, 0, -1]}}}\n";
}

// -d f_p / d x_p at rest [N/m], by central differences of the tet force
Mat3 own_block(const std::shared_ptr<const Model>& m, int p) {
  Simulation sim(m);
  State& s = sim.state();
  const double eps = 1e-7;  // [m], against 10 mm elements
  Mat3 H;
  for (int a = 0; a < 3; ++a) {
    Vec3 f[2];
    for (int k = 0; k < 2; ++k) {
      s.x = m->rest_pos;
      s.x[p][a] += k == 0 ? eps : -eps;
      for (Vec3& v : s.f) v.setZero();
      add_tet_elastic_forces(*m, s, TetPass::All, 1);
      f[k] = s.f[p];
    }
    H.col(a) = -(f[0] - f[1]) / (2 * eps);
  }
  return 0.5 * (H + H.transpose());
}

void expect_bounded(double poisson) {
  const auto m = test::compile_text(block_yaml(poisson));
  ASSERT_GT(m->tets.count(), 0);
  const std::vector<double> d = stiffness_proxy(*m);
  int checked = 0;
  for (int p = 0; p < m->particle_count(); p += 7) {
    if (m->inv_mass[p] == 0.0 || m->tets.node_slot[p] < 0) continue;
    const Mat3 H = own_block(m, p);
    const double trace = H.trace();
    const double top = Eigen::SelfAdjointEigenSolver<Mat3>(H).eigenvalues().maxCoeff();
    EXPECT_GE(d[p], top * (1 - 1e-5)) << "nu " << poisson << ", particle " << p << ": the proxy under the block's largest eigenvalue";
    EXPECT_LE(d[p], trace * (1 + 1e-5)) << "nu " << poisson << ", particle " << p << ": the proxy over the block's trace";
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(StiffnessProxy, TetBlockLiesBetweenTheOwnBlocksLargestEigenvalueAndTrace) {
  expect_bounded(0.30);
  expect_bounded(0.45);  // the fat's: the nodal pressure dominates
  expect_bounded(0.49);
}

}  // namespace
}  // namespace ps
