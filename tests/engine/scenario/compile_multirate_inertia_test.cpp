// solver.multirate_inertia (engine/scenario/compile_time_step.cpp partition_tet_rates_with_inertia):
// at a tick longer than the soft bulk's own stable step, particles that fall a little short of it
// get up to F times their inertial mass so that their elements join the multi-rate slow group.
// What must hold: the slow group grows and its estimate admits the tick; no particle gets more
// than F times its own inertia, and only the vertices of slow elements get any; gravity keeps the
// physical mass; the walls' vertices and the implicit pressure's nodes never get any; the scene
// settles to the same equilibrium as the plain run and comes to rest; bad values are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/scenario/model_hash.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

// A soft block (3 kPa, its own step ~1.2-2 ms at 10 mm) with a stiff inclusion, at a 2 ms tick of
// four substeps: without the inertia only ~5 % of its elements admit the tick.
std::string block_yaml(const std::string& solver) {
  return "name: multirate_inertia_block\nsolver: " + solver +
         "\ntime: {dt_ms: 2, substeps: 4, duration_s: 1}\ngravity_m_s2: [0, 0, -9.81]\nmaterials:\n"
         "  soft: {young_kpa: 3, density_kg_m3: 940, damping_1_s: 30, model: tet, poisson: 0.45}\ncomponents:\n"
         "  - {name: b, material: soft, spacing_mm: 10, box: {min_mm: [0, 0, 0], max_mm: [80, 80, 60]}}\n"
         "overrides:\n  - {component: b, region: {sphere: {center_mm: [40, 40, 30], radius_mm: 12}}, young_kpa: 300}\n"
         "constraints:\n  - fix: {component: b, region: {half_space: {point_mm: [0, 0, 1], normal: [0, 0, -1]}}}\n";
}

constexpr double kFactor = 4.0;

TEST(MultirateInertia, MovesTheSoftBulkIntoTheSlowGroup) {
  const auto plain = test::compile_text(block_yaml("{multirate: true}"));
  const auto m = test::compile_text(block_yaml("{multirate: true, multirate_inertia: 4}"));
  const TetElements& te = m->tets;
  const int slow = te.count() - te.fast_count, slow_plain = plain->tets.count() - plain->tets.fast_count;
  EXPECT_LT(slow_plain, te.count() / 10);
  EXPECT_GT(slow, 3 * te.count() / 4) << "the soft bulk joins the slow group";
  EXPECT_GT(te.fast_count, 0) << "the inclusion stays fast: it would need far more than 4x";
  EXPECT_GE(0.9 * estimate_stable_dt(*m, TetPass::SlowOnly), m->dt) << "the slow group admits the tick";
  EXPECT_EQ(m->substeps, plain->substeps);
  std::vector<uint8_t> in_slow(m->particle_count(), 0);
  for (int k = 4 * te.fast_count; k < 4 * te.count(); ++k) in_slow[te.v[k]] = 1;
  int scaled = 0;
  double added = 0.0;  // [kg]
  for (int p = 0; p < m->particle_count(); ++p) {
    EXPECT_EQ(m->mass[p], plain->mass[p]) << "gravity keeps the physical mass, particle " << p;
    if (plain->inv_mass[p] == 0.0) {
      EXPECT_EQ(m->inv_mass[p], 0.0);
      continue;
    }
    const double factor = plain->inv_mass[p] / m->inv_mass[p];  // inertial mass / the plain model's
    EXPECT_GE(factor, 1.0) << "particle " << p;
    EXPECT_LE(factor, kFactor * (1 + 1e-12)) << "particle " << p;
    if (factor > 1.0) {
      ++scaled;
      added += 1.0 / m->inv_mass[p] - 1.0 / plain->inv_mass[p];
      EXPECT_TRUE(in_slow[p]) << "inertia on particle " << p << ", which is in no slow element";
      // the damping force c m v is kept: the rate falls by the same factor
      EXPECT_NEAR(m->damping[p] * factor, plain->damping[p], 1e-12 * plain->damping[p]) << "particle " << p;
    }
  }
  EXPECT_GT(scaled, 0);
  EXPECT_NEAR(m->added_inertia, added, 1e-9 * added) << "the report counts what was added";
}

// With stiffness damping the particle's limit is the damped one, (2 / w)(sqrt(1 + z^2) - z): the
// inertia is sized to it, and the slow group still admits the tick.
TEST(MultirateInertia, SizesTheInertiaToTheDampedLimit) {
  const auto m = test::compile_text(block_yaml("{multirate: true, multirate_inertia: 4, stiffness_damping_s: 2.5e-5}"));
  const auto undamped = test::compile_text(block_yaml("{multirate: true, multirate_inertia: 4}"));
  ASSERT_GT(m->stiffness_damping, 0.0);
  EXPECT_GT(m->tets.count() - m->tets.fast_count, 3 * m->tets.count() / 4);
  EXPECT_GE(0.9 * estimate_stable_dt(*m, TetPass::SlowOnly), m->dt);
  EXPECT_GT(m->added_inertia, undamped->added_inertia) << "the damped limit is shorter: more inertia for the same tick";
}

TEST(MultirateInertia, SettlesToThePlainEquilibriumAndComesToRest) {
  const auto m = test::compile_text(block_yaml("{multirate: true, multirate_inertia: 4}"));
  const auto plain = test::compile_text(block_yaml("{multirate: false}"));
  Simulation a(m), b(plain);
  for (int i = 0; i < 1500; ++i) {  // 3 s
    ASSERT_TRUE(a.tick()) << a.state().fault.describe(*m);
    ASSERT_TRUE(b.tick()) << b.state().fault.describe(*plain);
  }
  // the particles are the same; the element order differs, which does not change the statics
  double worst = 0.0, sag = 0.0;  // [m]
  for (int p = 0; p < m->particle_count(); ++p) {
    worst = std::max(worst, (a.state().x[p] - b.state().x[p]).norm());
    sag = std::max(sag, (b.state().x[p] - plain->rest_pos[p]).norm());
  }
  EXPECT_GT(sag, 1e-3);
  EXPECT_LT(worst, 0.02 * sag) << "inertia does not move the equilibrium";
  EXPECT_LT(max_speed(a.state()), 1e-4) << "m/s";
}

// The default biopsy anatomy at a 3 ms tick (at its file's 2 ms the fat joins the slow group with
// about no inertia): the walls (shells) and the gland's implicit-pressure nodes keep their
// inertia whatever the factor, and the fat's slow group grows.
TEST(MultirateInertia, NeverOnTheWallsOrTheGland) {
  ScenarioSpec file = parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
  ASSERT_GT(file.multirate_inertia, 1.0) << "the shipped scene uses it";
  file.dt = 3e-3;
  file.substeps = 6;
  ScenarioSpec without = file;
  without.multirate_inertia = 1.0;
  const auto m = compile_scenario(file);
  const auto plain = compile_scenario(without);
  EXPECT_GT(m->tets.count() - m->tets.fast_count, plain->tets.count() - plain->tets.fast_count);
  std::vector<uint8_t> kept(m->particle_count(), 0);
  for (int v : m->shells.tri) kept[v] = 1;
  const TetElements& te = m->tets;
  int implicit_nodes = 0;
  for (size_t a = 0; a < te.nodes.size(); ++a)
    if (te.node_kappa[a] > 0.0 && te.node_kappa_explicit[a] == 0.0) {
      kept[te.nodes[a]] = 1;
      ++implicit_nodes;
    }
  ASSERT_GT(implicit_nodes, 0);
  ASSERT_FALSE(m->shells.tri.empty());
  int fat_scaled = 0;
  const int fat = m->find_component("fat");
  ASSERT_GE(fat, 0);
  for (int p = 0; p < m->particle_count(); ++p) {
    if (kept[p]) EXPECT_EQ(m->inv_mass[p], plain->inv_mass[p]) << "particle " << p;
    const Component& c = m->components[fat];
    if (p >= c.first_particle && p < c.first_particle + c.particle_count) fat_scaled += m->inv_mass[p] < plain->inv_mass[p];
  }
  EXPECT_GT(fat_scaled, 0);
}

TEST(MultirateInertia, RefusedWithoutMultirateOrOutOfRange) {
  test::expect_refused_with_field(block_yaml("{multirate: false, multirate_inertia: 4}"), "solver.multirate_inertia");
  test::expect_refused_with_field(block_yaml("{multirate: true, multirate_inertia: 0.5}"), "solver.multirate_inertia");
  test::expect_refused_with_field(block_yaml("{multirate: true, multirate_inertia: 100}"), "solver.multirate_inertia");
  // 1 is off: the plain partition, the model as without the key
  const auto one = test::compile_text(block_yaml("{multirate: true, multirate_inertia: 1}"));
  const auto plain = test::compile_text(block_yaml("{multirate: true}"));
  EXPECT_EQ(model_hash(*one), model_hash(*plain));
}

}  // namespace
}  // namespace ps
