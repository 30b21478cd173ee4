// Implicit nodal pressure (engine/step/tet_pressure.cpp, engine/model/tet_pressure.cpp): the
// stored factor solves the constraint system built here independently (finite differences of the
// node volumes), the static equilibrium is that of the explicit pressure (the same energy), the
// pressure no longer sets the stable substep, the step neither allocates nor loses determinism,
// and the scenario keys are checked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "engine/model/tet_pressure.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

// a 40 x 40 x 30 mm block of nearly incompressible gel on a fixed base, under gravity along -z
std::string block_yaml(const std::string& pressure, int substeps, const std::string& solver = "") {
  return "name: block\ntime: {dt_ms: 1, substeps: " + std::to_string(substeps) +
         ", duration_s: 1}\ngravity_m_s2: [0, 0, -9.81]\n" + solver +
         "materials:\n  gel: {young_kpa: 5, poisson: 0.49, damping_1_s: 60, model: tet, pressure: " + pressure +
         "}\ncomponents:\n  - name: block\n    material: gel\n    spacing_mm: 8\n"
         "    box: {min_mm: [0, 0, 0], max_mm: [40, 40, 30]}\n"
         "constraints:\n  - fix: {component: block, region: {half_space: {point_mm: [0, 0, 1], normal: [0, 0, -1]}}}\n";
}

// node volume shares V_n(x) of the rows' nodes, from the elements (the definition of C_n + V0_n)
std::vector<double> node_volumes(const Model& m, const std::vector<Vec3>& x) {
  const TetPressure& tp = m.tet_pressure;
  std::vector<double> v(tp.size(), 0.0);
  for (int t = 0; t < m.tets.count(); ++t) {
    const int* e = &m.tets.v[4 * t];
    const double vol = (x[e[1]] - x[e[0]]).dot((x[e[2]] - x[e[0]]).cross(x[e[3]] - x[e[0]])) / 6.0;
    for (int i = 0; i < 4; ++i)
      if (const int r = tp.slot_row[m.tets.node_slot[e[i]]]; r >= 0) v[r] += 0.25 * vol;
  }
  return v;
}

TEST(TetPressure, FactorSolvesTheConstraintSystem) {
  auto m = test::compile_text(block_yaml("implicit", 1));
  const TetPressure& tp = m->tet_pressure;
  const int k = tp.size(), n = m->particle_count();
  ASSERT_GT(k, 20);
  EXPECT_EQ(k, static_cast<int>(m->tets.nodes.size()));  // every node of the block is implicit
  // J by central differences of the node volumes at rest: J[r][3p + a]
  std::vector<std::vector<double>> J(k, std::vector<double>(3 * n, 0.0));
  std::vector<Vec3> x = m->rest_pos;
  const double eps = 1e-6;
  for (int p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) {
      x[p][a] += eps;
      const auto up = node_volumes(*m, x);
      x[p][a] -= 2 * eps;
      const auto dn = node_volumes(*m, x);
      x[p][a] += eps;
      for (int r = 0; r < k; ++r) J[r][3 * p + a] = (up[r] - dn[r]) / (2 * eps);
    }
  auto w = [&](int p, int a) { return (m->locked_axes[p] & (1u << a)) ? 0.0 : m->inv_mass[p]; };
  // b = (J W J^T + alpha / h^2) y for a fixed y, then the stored factor must give y back
  std::vector<double> y(k), b(k, 0.0), jty(3 * n, 0.0);
  for (int r = 0; r < k; ++r) y[r] = std::cos(0.7 * r) * 1e-3;
  for (int r = 0; r < k; ++r)
    for (int q = 0; q < 3 * n; ++q) jty[q] += J[r][q] * y[r];
  for (int r = 0; r < k; ++r) {
    for (int q = 0; q < 3 * n; ++q) b[r] += J[r][q] * w(q / 3, q % 3) * jty[q];
    b[r] += tp.alpha[r] / (tp.h * tp.h) * y[r];
  }
  std::vector<double> work(k);
  solve_tet_pressure(tp, b.data(), work.data());
  double err = 0, scale = 0;
  for (int r = 0; r < k; ++r) { err = std::max(err, std::abs(b[r] - y[r])); scale = std::max(scale, std::abs(y[r])); }
  EXPECT_LE(err, 1e-6 * scale);
}

// The implicit pressure has the explicit pressure's energy, so both settle to the same static
// equilibrium; the implicit run does it at a substep the explicit pressure cannot take.
TEST(TetPressure, SettlesWhereTheExplicitPressureSettles) {
  auto explicit_m = test::compile_text(block_yaml("explicit", 1));
  auto implicit_m = test::compile_text(block_yaml("implicit", 1));
  // the pressure wave no longer sets the substep: the estimate grows by about sqrt((kappa + mu) / mu)
  EXPECT_GT(implicit_m->stable_dt_estimate, 3.0 * explicit_m->stable_dt_estimate);
  ASSERT_GT(explicit_m->substeps, implicit_m->substeps);
  Simulation a(explicit_m), b(implicit_m);
  for (int i = 0; i < 1500; ++i) {
    ASSERT_TRUE(a.tick()) << a.state().fault.describe(*explicit_m);
    ASSERT_TRUE(b.tick()) << b.state().fault.describe(*implicit_m);
  }
  double sag = 0, diff = 0, speed = 0;
  for (int p = 0; p < explicit_m->particle_count(); ++p) {
    sag = std::max(sag, (a.state().x[p] - explicit_m->rest_pos[p]).norm());
    diff = std::max(diff, (a.state().x[p] - b.state().x[p]).norm());
    speed = std::max(speed, b.state().v[p].norm());
  }
  EXPECT_GT(sag, 0.5e-3);          // gravity does sag the soft block
  EXPECT_LT(diff, 0.02 * sag);     // to the same equilibrium
  EXPECT_LT(speed, 1e-4);          // at rest [m/s]
  // and the volume term is honoured: node volumes change by about as little as explicitly
  const auto va = node_volumes(*implicit_m, a.state().x), vb = node_volumes(*implicit_m, b.state().x);
  double ja = 0, jb = 0;
  for (int r = 0; r < implicit_m->tet_pressure.size(); ++r) {
    ja = std::max(ja, std::abs(va[r] / implicit_m->tet_pressure.vol0[r] - 1.0));
    jb = std::max(jb, std::abs(vb[r] / implicit_m->tet_pressure.vol0[r] - 1.0));
  }
  EXPECT_LT(jb, 1.5 * ja + 1e-6);
}

TEST(TetPressure, StepDoesNotAllocateAndIsDeterministic) {
  auto m = test::compile_text(block_yaml("implicit", 1, "solver: {pressure_iterations: 2}\n"));
  ASSERT_EQ(m->tet_pressure.iterations, 2);
  Simulation a(m), b(m);
  const auto& pl = a.pipeline();
  EXPECT_NE(std::find(pl.begin(), pl.end(), Stage::TetPressure), pl.end());
  ASSERT_TRUE(a.tick());
  const long before = test::allocation_count();
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(a.tick());
  EXPECT_EQ(test::allocation_count() - before, 0);
  for (int i = 0; i < 21; ++i) ASSERT_TRUE(b.tick());
  for (int p = 0; p < m->particle_count(); ++p) EXPECT_EQ(a.state().x[p], b.state().x[p]);
}

TEST(TetPressure, FourWideCorrectionsEqualOneElementAtATimeBitForBit) {
  auto m = test::compile_text(block_yaml("implicit", 1));
  const TetPressure& tp = m->tet_pressure;
  const int ntp = static_cast<int>(tp.tets.size()), k = tp.size(), n = m->particle_count();
  ASSERT_GT(ntp, 16);
  std::mt19937 rng(7);
  std::normal_distribution<double> N(0.0, 1e-3);  // 1 mm jitter on an 8 mm spacing
  std::vector<Vec3> x(m->rest_pos);
  for (Vec3& p : x) p += Vec3(N(rng), N(rng), N(rng));
  // multiplier steps with many rows at zero, so that some elements' shares are zero and skipped
  std::vector<double> dl(k);
  std::bernoulli_distribution zero(0.7);
  for (double& d : dl) d = zero(rng) ? 0.0 : N(rng);
  int skipped = 0;
  for (int j = 0; j < ntp; ++j) {
    double share = 0.0;
    for (int i = 0; i < 4; ++i)
      if (const int r = tp.tet_row[4 * j + i]; r >= 0) share += dl[r];
    skipped += share == 0.0;
  }
  EXPECT_GT(skipped, 0);
  EXPECT_LT(skipped, ntp);
  // every count of elements mod 4, and the whole list
  for (int count : {1, 2, 3, 5, ntp - 3, ntp - 2, ntp - 1, ntp}) {
    std::vector<Vec3> wide(n, Vec3::Zero()), one(n, Vec3::Zero());
    pressure_corrections(tp.tet_v.data(), tp.tet_row.data(), count, dl.data(), x.data(), wide.data());
    // one element at a time: each call takes the scalar path
    for (int j = 0; j < count; ++j) pressure_corrections(&tp.tet_v[4 * j], &tp.tet_row[4 * j], 1, dl.data(), x.data(), one.data());
    int differing = 0, moved = 0;
    for (int p = 0; p < n; ++p)
      for (int a = 0; a < 3; ++a) {
        differing += std::memcmp(&wide[p][a], &one[p][a], sizeof(double)) != 0;
        moved += one[p][a] != 0.0;
      }
    EXPECT_EQ(differing, 0) << count << " elements";
    EXPECT_GT(moved, 0) << count << " elements";
  }
}

TEST(TetPressure, ExplicitSceneHasNoStage) {
  auto m = test::compile_text(block_yaml("explicit", 1));
  EXPECT_EQ(m->tet_pressure.size(), 0);
  Simulation sim(m);
  const auto& pl = sim.pipeline();
  EXPECT_EQ(std::find(pl.begin(), pl.end(), Stage::TetPressure), pl.end());
}

TEST(TetPressure, BadKeysAreRefusedWithTheirField) {
  const auto expect_field = test::expect_refused_with_field;
  expect_field(block_yaml("sideways", 1), "materials.gel.pressure");
  expect_field(block_yaml("implicit", 1, "solver: {pressure_iterations: 0}\n"), "solver.pressure_iterations");
  expect_field("name: t\nmaterials:\n  gel: {young_kpa: 10, pressure: implicit}\ncomponents:\n"
               "  - {name: c, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n",
               "materials.gel.pressure");
}

}  // namespace
}  // namespace ps
