// Shape-memory force properties (paper §3.2): zero at rest, invariant under rigid motion,
// momentum-conserving, and degenerate neighbourhoods refused at compile time.
#include "engine/model/discrete_coordinates.h"

#include <gtest/gtest.h>

#include <random>

#include "engine/step/stages.h"
#include "engine/util/error.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

double max_force(const State& s) {
  double f = 0;
  for (const Vec3& v : s.f) f = std::max(f, v.norm());
  return f;
}

// reference scale: the force one particle feels when displaced by one spacing alone
double force_scale(const Model& m) { return m.k_e[0] * m.components[0].spacing; }

std::string cylinder_yaml() {
  return "name: cyl\nmaterials: {soft: {young_kpa: 60}}\ncomponents:\n"
         "  - {name: c, material: soft, spacing_mm: 6, cylinder: {radius_mm: 19, length_mm: 60, axis: [0.2, 0.3, 1]}}\n";
}

class ShapeMemory : public ::testing::TestWithParam<std::string> {};

TEST_P(ShapeMemory, ZeroForceAtRest) {
  auto m = test::compile_text(GetParam());
  State s = make_state(*m);
  for (auto& f : s.f) f.setZero();
  add_shape_memory_forces(*m, s);
  EXPECT_LE(max_force(s), 1e-12 * force_scale(*m));
}

TEST_P(ShapeMemory, ZeroForceAfterRigidTranslationAndRotation) {
  auto m = test::compile_text(GetParam());
  State s = make_state(*m);
  const Mat3 R = (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(2.1, Vec3::UnitZ())).toRotationMatrix();
  const Vec3 t(0.013, -0.4, 0.21);
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = m->rest_pos[p] + t;
  for (auto& f : s.f) f.setZero();
  add_shape_memory_forces(*m, s);
  EXPECT_LE(max_force(s), 1e-9 * force_scale(*m)) << "translation";
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = R * m->rest_pos[p] + t;
  for (auto& f : s.f) f.setZero();
  add_shape_memory_forces(*m, s);
  EXPECT_LE(max_force(s), 1e-9 * force_scale(*m)) << "rotation";
}

TEST_P(ShapeMemory, InternalForcesSumToZero) {
  auto m = test::compile_text(GetParam());
  State s = make_state(*m);
  std::mt19937 rng(7);
  std::normal_distribution<double> N(0.0, 0.003);
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
  for (auto& f : s.f) f.setZero();
  add_shape_memory_forces(*m, s);
  Vec3 sum = Vec3::Zero();
  double mag = 0;
  for (const Vec3& f : s.f) { sum += f; mag += f.norm(); }
  ASSERT_GT(mag, 0.0);
  EXPECT_LE(sum.norm(), 1e-12 * mag);
}

TEST_P(ShapeMemory, DeformationMakesARestoringForce) {
  auto m = test::compile_text(GetParam());
  State s = make_state(*m);
  const int p = m->particle_count() / 2;
  s.x[p] += Vec3(0.002, 0, 0);
  for (auto& f : s.f) f.setZero();
  add_shape_memory_forces(*m, s);
  EXPECT_LT(s.f[p].x(), 0.0);  // pulled back toward its attractor
}

INSTANTIATE_TEST_SUITE_P(Shapes, ShapeMemory,
                         ::testing::Values(test::cube_yaml(40, 10, false, false), test::cube_yaml(30, 10, true, false),
                                           cylinder_yaml()),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                           return std::string(i.index == 0 ? "Cube" : i.index == 1 ? "IncompressibleCube" : "TiltedCylinder");
                         });

TEST(DiscreteCoordinates, CollinearNeighbourhoodRejectedNamingTheParticle) {
  Model m;
  m.components.push_back(Component{"rod"});
  m.rest_pos = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  m.component_of = {0, 0, 0, 0};
  m.shape_memory = {1, 0, 0, 0};
  m.nbr_start = {0, 3, 3, 3, 3};
  m.nbr = {1, 2, 3};
  try {
    compute_discrete_coordinates(m);
    FAIL() << "collinear neighbourhood accepted";
  } catch (const CompileError& e) {
    EXPECT_NE(std::string(e.what()).find("particle 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'rod'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos) << e.what();
  }
}

TEST(DiscreteCoordinates, TooFewNeighboursRejected) {
  Model m;
  m.components.push_back(Component{"sheet"});
  m.rest_pos = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.component_of = {0, 0, 0};
  m.shape_memory = {0, 1, 0};
  m.nbr_start = {0, 0, 2, 2};
  m.nbr = {0, 2};
  EXPECT_THROW(compute_discrete_coordinates(m), CompileError);
}

TEST(DiscreteCoordinates, WeightsSumToOneAndReproduceRest) {
  auto m = test::compile_text(cylinder_yaml());
  for (int p = 0; p < m->particle_count(); ++p) {
    double w = 0;
    for (int a = m->nbr_start[p]; a < m->nbr_start[p + 1]; ++a) w += m->nbr_w[a];
    ASSERT_NEAR(w, 1.0, 1e-12) << "particle " << p;
  }
}

TEST(DiscreteCoordinates, LatticeInteriorHasEightOffsetTripletsOfTwenty) {
  // design note: with 6 face neighbours, 20 triplets are valid and 8 have beta != 0
  auto m = test::compile_text(test::cube_yaml(40, 10, false, false));
  int checked = 0;
  for (int p = 0; p < m->particle_count(); ++p) {
    if (m->on_surface[p]) continue;
    EXPECT_EQ(m->triplet_count[p], 20);
    EXPECT_EQ(m->beta_start[p + 1] - m->beta_start[p], 8);
    ++checked;
  }
  EXPECT_EQ(checked, 27);
}

}  // namespace
}  // namespace ps
