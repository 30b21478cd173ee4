// Multi-rate tet elements (solver.multirate; engine/scenario/compile_time_step.cpp partition_tet_rates,
// engine/step/tet_elastic.cpp TetPass): a soft block with a stiff inclusion splits into a fast
// group (the inclusion and its neighbourhood, every substep) and a slow group (once per tick: the
// part of its force that differs from a held force as two half kicks at the tick's ends, the
// symmetric impulse split, and the held force on every substep). The split run must stay stable,
// settle to the same equilibrium as the plain run and come to rest, and be deterministic.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/scenario/compile.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

std::string block_yaml(bool multirate) {
  return std::string("name: multirate_block\nsolver: {multirate: ") + (multirate ? "true" : "false") +
         "}\ntime: {dt_ms: 1, substeps: 1, duration_s: 1}\ngravity_m_s2: [0, 0, -9.81]\nmaterials:\n"
         "  soft: {young_kpa: 3, damping_1_s: 30, model: tet}\ncomponents:\n"
         "  - {name: b, material: soft, spacing_mm: 10, box: {min_mm: [0, 0, 0], max_mm: [80, 80, 60]}}\n"
         "overrides:\n  - {component: b, region: {sphere: {center_mm: [40, 40, 30], radius_mm: 12}}, young_kpa: 300}\n"
         "constraints:\n  - fix: {component: b, region: {half_space: {point_mm: [0, 0, 1], normal: [0, 0, -1]}}}\n";
}

TEST(TetMultirate, SplitsTheStiffInclusionFromTheSoftBlock) {
  auto m = test::compile_text(block_yaml(true));
  const TetElements& te = m->tets;
  ASSERT_TRUE(te.multirate());
  EXPECT_GT(te.fast_count, 0);
  EXPECT_GT(te.count() - te.fast_count, te.fast_count);  // most of the soft block is slow
  // the fast group's substep is what the substep count follows; the slow group admits the tick
  EXPECT_GE(m->substeps, 2);
  auto plain = test::compile_text(block_yaml(false));
  EXPECT_FALSE(plain->tets.multirate());
  EXPECT_EQ(plain->substeps, m->substeps);  // the inclusion sets both
}

TEST(TetMultirate, SettlesToThePlainEquilibriumAndIsDeterministic) {
  auto m = test::compile_text(block_yaml(true));
  auto plain = test::compile_text(block_yaml(false));
  Simulation a(m), b(plain), c(m);
  for (int i = 0; i < 1500; ++i) {
    ASSERT_TRUE(a.tick()) << a.state().fault.describe(*m);
    ASSERT_TRUE(b.tick()) << b.state().fault.describe(*plain);
  }
  // same particles in the same order: the statics do not depend on when forces are applied
  double worst = 0.0, sag = 0.0;
  for (int p = 0; p < m->particle_count(); ++p) {
    worst = std::max(worst, (a.state().x[p] - b.state().x[p]).norm());
    sag = std::max(sag, (b.state().x[p] - plain->rest_pos[p]).norm());
  }
  EXPECT_GT(sag, 1e-3);            // the block does sag [m]
  EXPECT_LT(worst, 0.02 * sag);    // and both runs agree to 2 % of it
  for (int i = 0; i < 1500; ++i) ASSERT_TRUE(c.tick());
  EXPECT_EQ(hash_state(a.state()), hash_state(c.state()));
  EXPECT_LT(max_speed(b.state()), 1e-4) << "m/s";
}

// The split run comes to rest. Kicking the whole slow force (the plain symmetric split) left a
// particle between the groups on an orbit within the tick, kicked by its slow elements against
// the steady pull of its fast ones: here particle 283 kept 0.055 m/s at every tick boundary for
// as long as it ran (measured to 6 s), on the biopsy scene 14 mm/s. With the held part of the slow
// force spread over the substeps (State::tet_slow_hold) the kicks vanish at rest: 4e-10 m/s
// after 3 s. (It settles more slowly than the plain run, which is at 1e-10 m/s after 1.5 s.)
TEST(TetMultirate, ABodyAtRestIsAtRest) {
  auto m = test::compile_text(block_yaml(true));
  Simulation a(m);
  for (int i = 0; i < 3000; ++i) ASSERT_TRUE(a.tick()) << a.state().fault.describe(*m);
  // and it stays there, tick after tick
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(a.tick());
    EXPECT_LT(max_speed(a.state()), 1e-6) << "m/s at tick " << 3001 + i;
  }
}

// Save between ticks and restore into another simulation: the carried slow force travels with the
// state, so both continue bit-identically.
TEST(TetMultirate, SaveRestoreCarriesTheSlowForce) {
  auto m = test::compile_text(block_yaml(true));
  Simulation a(m), b(m);
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(a.tick());
  std::vector<uint8_t> buf;
  a.save(buf);
  b.restore(buf);
  for (int i = 0; i < 50; ++i) { ASSERT_TRUE(a.tick()); ASSERT_TRUE(b.tick()); }
  EXPECT_EQ(hash_state(a.state()), hash_state(b.state()));
}

// With two substeps per tick the opening half kick T/2 F is F over the first substep: the first
// substep's force is the plain run's.
TEST(TetMultirate, TwoSubstepTickStartEqualsAll) {
  auto m = test::compile_text(block_yaml(true));
  State s1 = make_state(*m), s2 = make_state(*m);
  for (int p = 0; p < m->particle_count(); ++p) {
    const Vec3 d(1e-3 * std::sin(3.0 * p), 1e-3 * std::cos(5.0 * p), 1e-3 * std::sin(7.0 * p));
    s1.x[p] = s2.x[p] = m->rest_pos[p] + d;
    s1.f[p].setZero();
    s2.f[p].setZero();
  }
  add_tet_elastic_forces(*m, s1, TetPass::All);
  add_tet_elastic_forces(*m, s2, TetPass::TickStart, 2);
  for (int p = 0; p < m->particle_count(); ++p) EXPECT_LT((s1.f[p] - s2.f[p]).norm(), 1e-12 * (1.0 + s1.f[p].norm()));
}

}  // namespace
}  // namespace ps
