// Strain-memory force (engine/step/strain_memory.cpp): it is the exact gradient of its energy,
// vanishes for rigid motions, conserves momentum, passes the patch test (a uniform strain is in
// equilibrium up to the surface), and its mapping gives the continuum's energy density.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/model/material.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

// E = 10 kPa strain-model cube (side mm, spacing mm) or the truth-cylinder-like mesh fill
std::string strain_cube_yaml(double side = 40, double h = 10, const std::string& extra = "") {
  const std::string s = std::to_string(side);
  return "name: strain_cube\nmaterials:\n  gel: {young_kpa: 10, incompressible: true, model: strain" + extra +
         "}\ncomponents:\n  - name: cube\n    material: gel\n    spacing_mm: " + std::to_string(h) +
         "\n    box: {min_mm: [0, 0, 0], max_mm: [" + s + ", " + s + ", " + s + "]}\n";
}
const char* kCylinderYaml =
    "name: strain_cyl\nmaterials: {soft: {young_kpa: 60, model: strain}}\ncomponents:\n"
    "  - {name: c, material: soft, spacing_mm: 6, cylinder: {radius_mm: 12, length_mm: 30}}\n";

std::vector<Vec3> strain_forces(const Model& m, State& s) {
  for (auto& f : s.f) f.setZero();
  add_strain_memory_forces(m, s, 100);  // rotation converged
  return s.f;
}

TEST(StrainMemoryForce, IsTheGradientOfTheStrainEnergy) {
  for (const std::string& yaml : {strain_cube_yaml(30, 10), std::string(kCylinderYaml)}) {
    auto m = test::compile_text(yaml);
    ASSERT_GT(m->strain.count(), 0);
    State s = make_state(*m);
    // a large deformation: stretch, shear, a rotation of 0.5 rad and noise of 1 mm
    const Mat3 R = Eigen::AngleAxisd(0.5, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    Mat3 F;
    F << 1.2, 0.1, 0.0, -0.05, 0.9, 0.1, 0.0, 0.2, 1.05;
    std::mt19937 rng(5);
    std::normal_distribution<double> N(0.0, 1e-3);
    for (int p = 0; p < m->particle_count(); ++p) s.x[p] = R * F * m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
    const std::vector<Vec3> force = strain_forces(*m, s);
    const auto [worst, scale] = test::gradient_mismatch(s, force, 3, [&](State& st) { return strain_memory_energy(*m, st); });
    ASSERT_GT(scale, 0.0);
    EXPECT_LE(worst, 1e-6 * scale) << m->name;
    // momentum: forces sum to zero, torques too
    Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
    for (int p = 0; p < m->particle_count(); ++p) { sum += force[p]; torque += s.x[p].cross(force[p]); }
    EXPECT_LE(sum.norm(), 1e-10 * scale) << m->name;
    // exact only at the exact polar rotation; the iteration stops at |omega| < 1e-9 rad
    EXPECT_LE(torque.norm(), 1e-7 * scale * 0.05) << m->name;
  }
}

TEST(StrainMemoryForce, ZeroAtRestAndForRigidMotions) {
  auto m = test::compile_text(kCylinderYaml);
  State s = make_state(*m);
  const double scale = m->strain.mu2v[0] / 6e-3 * 1e-3 / 6e-3;  // force of a 1 mm misfit [N]
  auto largest = [&] {
    double f = 0;
    for (const Vec3& v : strain_forces(*m, s)) f = std::max(f, v.norm());
    return f;
  };
  EXPECT_LE(largest(), 1e-12 * scale);
  const Mat3 R = Eigen::AngleAxisd(2.0, Vec3(-1, 0.3, 0.7).normalized()).toRotationMatrix();
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = R * m->rest_pos[p] + Vec3(0.1, -0.2, 0.05);
  // R found from identity, 2 rad away, to the iteration's 1e-9 rad: a misfit of ~1e-11 m
  EXPECT_LE(largest(), 1e-8 * scale);
}

// Patch test: under a uniform deformation F every particle's strain force is the uniform stress
// acting on its share a_i = dV/dx_i of the surface: zero inside, -P a_i on the surface.
TEST(StrainMemoryForce, PassesThePatchTest) {
  auto m = test::compile_text(kCylinderYaml);
  State s = make_state(*m);
  Mat3 F;
  F << 1.05, 0.02, 0.0, 0.0, 0.97, 0.01, 0.03, 0.0, 1.02;
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = F * m->rest_pos[p];
  const std::vector<Vec3> force = strain_forces(*m, s);
  std::vector<Vec3> area(m->particle_count(), Vec3::Zero());
  for (const auto& f : m->surfaces[0].faces)
    for (int k = 0; k < 3; ++k) area[f[k]] += m->rest_pos[f[(k + 1) % 3]].cross(m->rest_pos[f[(k + 2) % 3]]) / 6.0;
  // the stress of one cluster per unit volume (all clusters have the same F)
  const StrainClusters& sc = m->strain;
  double vol = 0;
  for (int p = 0; p < m->particle_count(); ++p) vol += area[p].dot(m->rest_pos[p]) / 3.0;
  double mu2 = 0, kv = 0;
  for (int c = 0; c < sc.count(); ++c) { mu2 += sc.mu2v[c]; kv += sc.k_v[c]; }
  const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat3 R = svd.matrixU() * svd.matrixV().transpose();
  const Mat3 cof = F.determinant() * F.inverse().transpose();
  const Mat3 P = (mu2 * (F - R) + kv * (F.determinant() - 1.0) * cof) / vol;  // [Pa]
  double worst = 0, scale = 0;
  for (int p = 0; p < m->particle_count(); ++p) {
    const Vec3 expect = -P * area[p];
    worst = std::max(worst, (force[p] - expect).norm());
    scale = std::max(scale, expect.norm());
  }
  ASSERT_GT(scale, 0.0);
  EXPECT_LE(worst, 1e-6 * scale);
}

// On the lattice, an interior cluster has k_r = 0.3 * 6 mu V_c / tr S = 0.3 mu V_c / h^2 (= 0.3 mu h when V_c = h^3,
// docs/model.md) and mu2v = 2 mu V_c, and a
// small uniform strain stores V (mu |eps|^2 + lambda/2 (tr eps)^2) in the whole body.
TEST(StrainMemoryMapping, LatticeConstantsAndEnergyDensity) {
  auto m = test::compile_text(strain_cube_yaml(40, 10, ", poisson: 0.3"));
  const StrainModuli sm = strain_moduli(10e3, 0.3);
  const int centre = 2 + 5 * (2 + 5 * 2);  // lattice point (2, 2, 2) of the 5x5x5 cube
  int c = 0;
  while (m->strain.centre[c] != centre) ++c;
  const double h = 0.01, v = 0.04 * 0.04 * 0.04 / 125.0;
  EXPECT_NEAR(m->strain.k_r[c], kStrainResidualFactor * sm.mu * 6.0 * v / (6.0 * h * h), 1e-9 * sm.mu * h);
  EXPECT_NEAR(m->strain.mu2v[c], 2.0 * sm.mu * v, 1e-12 * sm.mu * v);
  EXPECT_NEAR(m->strain.k_v[c], sm.lambda * v, 1e-12 * sm.lambda * v);
  State s = make_state(*m);
  Mat3 eps;
  eps << 1e-4, 2e-5, 0, 2e-5, -3e-5, 1e-5, 0, 1e-5, 5e-5;
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = (Mat3::Identity() + eps) * m->rest_pos[p];
  const double w = sm.mu * eps.squaredNorm() + 0.5 * sm.lambda * eps.trace() * eps.trace();
  EXPECT_NEAR(strain_memory_energy(*m, s), w * 0.04 * 0.04 * 0.04, 1e-3 * w * 0.04 * 0.04 * 0.04);
}

TEST(StrainMemoryMapping, SurfaceComponentIsRefused) {
  const std::string y =
      "name: t\nmaterials:\n  gel: {young_kpa: 10, model: strain}\ncomponents:\n"
      "  - {name: skin, material: gel, spacing_mm: 10, fill: surface, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n";
  try {
    test::compile_text(y);
    FAIL() << "a strain-model membrane was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "materials.gel.model");
    EXPECT_EQ(e.line(), 3);
  }
}

TEST(StrainMemoryMapping, BadKeysNameFileLineAndKey) {
  struct Case { std::string extra, key; };
  const Case cases[] = {{", model: fem", "materials.gel.model"},
                        {", poisson: 0.3", "materials.gel.poisson"},  // without model: strain
                        {", model: strain, poisson: 0.5", "materials.gel.poisson"},
                        {", model: strain, k_s_n_m: -2", "materials.gel.k_s_n_m"}};
  for (const Case& c : cases) {
    const std::string y = "name: t\nmaterials:\n  gel: {young_kpa: 10" + c.extra +
                          "}\ncomponents:\n  - {name: b, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n";
    try {
      parse_scenario_text(y, "m.yaml");
      ADD_FAILURE() << c.extra << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), c.key) << e.what();
      EXPECT_EQ(e.line(), 3) << e.what();
      EXPECT_NE(std::string(e.what()).find("m.yaml:3"), std::string::npos) << e.what();
    }
  }
}

// Inverted (mirrored, J = -1) and collapsed (every particle at one point, F = 0) bodies: the
// rotation stays proper and the force finite. A body crushed to 30 % of its height and released
// (damped) returns to its rest shape.
TEST(StrainMemoryForce, InvertedCollapsedAndCrushedBodies) {
  auto m = test::compile_text(
      "name: t\ntime: {dt_ms: 1, substeps: 1, duration_s: 1}\ngravity_m_s2: [0, 0, 0]\n"
      "materials:\n  gel: {young_kpa: 10, damping_1_s: 30, model: strain}\ncomponents:\n"
      "  - {name: b, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [30,30,30]}}\n");
  for (int config = 0; config < 2; ++config) {
    State s = make_state(*m);
    for (int p = 0; p < m->particle_count(); ++p) {
      s.x[p] = m->rest_pos[p];
      if (config == 0) s.x[p].z() = 0.03 - m->rest_pos[p].z();  // mirrored
      else s.x[p] = Vec3(0.01, 0.01, 0.01);                     // collapsed
    }
    for (const Vec3& f : strain_forces(*m, s)) EXPECT_TRUE(f.allFinite()) << config;
    for (const Quat& q : s.strain_rot) EXPECT_NEAR(q.norm(), 1.0, 1e-12) << config;
  }
  Simulation sim(m);
  State& s = sim.state();
  for (int p = 0; p < m->particle_count(); ++p) s.x[p].z() = 0.3 * m->rest_pos[p].z();
  s.x_prev = s.x;
  const double e0 = strain_memory_energy(*m, s);
  ASSERT_GT(e0, 0.0);
  for (int i = 0; i < 3000; ++i) ASSERT_TRUE(sim.tick()) << s.fault.describe(*m);
  EXPECT_LT(strain_memory_energy(*m, s), 1e-6 * e0);
}

// A paper-model scene compiles without the strain model: no clusters, no strain stage.
TEST(StrainMemoryMapping, PaperModelHasNoClusters) {
  auto m = test::compile_text(test::cube_yaml());
  EXPECT_EQ(m->strain.count(), 0);
}

}  // namespace
}  // namespace ps
