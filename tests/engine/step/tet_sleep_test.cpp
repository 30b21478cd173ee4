// Sleeping tissue (solver.sleep; engine/step/tet_sleep.cpp, engine/scenario/compile_sleep.cpp): a
// soft block on a fixed base settles under gravity and falls asleep; a load that reaches it
// later (its top pressed down by an imposed displacement) wakes it, and it ends where the run
// without sleeping ends. Until something sleeps the run is bit-identical to the plain one; the
// step allocates nothing; save/restore and reruns are bit-identical; bad keys are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

// 80 x 80 x 60 mm block of 3 kPa fat-like tissue at 10 mm spacing, fixed at its base; with
// `press`, its top 10 mm are pushed 6 mm down between 1.5 and 1.8 s (after it has settled)
std::string block_yaml(bool sleep, bool press, const std::string& solver_extra = "") {
  std::string y = std::string("name: sleep_block\nsolver: {sleep: ") + (sleep ? "true" : "false") + solver_extra +
                  "}\ntime: {dt_ms: 1, substeps: 2, duration_s: 1}\ngravity_m_s2: [0, 0, -9.81]\nmaterials:\n"
                  "  soft: {young_kpa: 3, damping_1_s: 30, model: tet}\ncomponents:\n"
                  "  - {name: b, material: soft, spacing_mm: 10, box: {min_mm: [0, 0, 0], max_mm: [80, 80, 60]}}\n"
                  "constraints:\n  - fix: {component: b, region: {half_space: {point_mm: [0, 0, 1], normal: [0, 0, -1]}}}\n";
  if (press)
    y += "  - displace: {component: b, region: {box: {min_mm: [30, 30, 55], max_mm: [50, 50, 61]}}, by_mm: [0, 0, -6], "
         "ramp_s: [1.5, 1.8]}\n";
  return y;
}

int asleep_count(const State& s) {
  int n = 0;
  for (uint8_t a : s.asleep) n += a;
  return n;
}

double worst_difference(const State& a, const State& b) {
  double w = 0.0;
  for (size_t p = 0; p < a.x.size(); ++p) w = std::max(w, (a.x[p] - b.x[p]).norm());
  return w;
}

TEST(TetSleep, OnlyTetParticlesThatNothingElseMovesMaySleep) {
  auto m = test::compile_text(block_yaml(true, true));
  ASSERT_TRUE(m->sleep.enabled());
  int may = 0, fixed = 0;
  for (int p = 0; p < m->particle_count(); ++p) {
    const uint8_t r = m->sleep.role[p];
    may += r == TetSleep::kMaySleep;
    fixed += r == TetSleep::kFixed;
    if (r == TetSleep::kMaySleep) EXPECT_EQ(m->locked_axes[p], 0) << "particle " << p;
  }
  EXPECT_EQ(may, m->sleep.eligible_count);
  EXPECT_GT(fixed, 0);                          // the base
  for (const ImposedDisplacement& d : m->imposed)  // the pressed patch never sleeps
    for (int p : d.particles) EXPECT_EQ(m->sleep.role[p], TetSleep::kAwake) << "particle " << p;
  EXPECT_GT(may, m->particle_count() / 2);
  auto plain = test::compile_text(block_yaml(false, true));
  EXPECT_FALSE(plain->sleep.enabled());
  Simulation sim(plain);
  const auto& pl = sim.pipeline();
  EXPECT_EQ(std::find(pl.begin(), pl.end(), Stage::Sleep), pl.end());  // absent where it is off
}

TEST(TetSleep, UntilSomethingSleepsTheRunIsThePlainRun) {
  auto m = test::compile_text(block_yaml(true, false));
  auto plain = test::compile_text(block_yaml(false, false));
  Simulation a(m), b(plain);
  for (int i = 0; i < m->sleep.hold_ticks - 1; ++i) {
    ASSERT_TRUE(a.tick());
    ASSERT_TRUE(b.tick());
  }
  EXPECT_EQ(asleep_count(a.state()), 0);
  EXPECT_EQ(hash_state(a.state()), hash_state(b.state()));
}

TEST(TetSleep, SettledBlockSleepsAndALoadWakesItToThePlainResult) {
  auto m = test::compile_text(block_yaml(true, true));
  auto plain = test::compile_text(block_yaml(false, true));
  Simulation a(m), b(plain);
  for (int i = 0; i < 1400; ++i) {  // settled, before the press starts at 1.5 s
    ASSERT_TRUE(a.tick()) << a.state().fault.describe(*m);
    ASSERT_TRUE(b.tick()) << b.state().fault.describe(*plain);
  }
  double sag = 0.0;
  for (int p = 0; p < plain->particle_count(); ++p) sag = std::max(sag, (b.state().x[p] - plain->rest_pos[p]).norm());
  EXPECT_GT(sag, 1e-3);  // it does sag [m]
  // asleep: (nearly) every particle that may, and most elements held
  EXPECT_GE(asleep_count(a.state()), 0.9 * m->sleep.eligible_count);
  EXPECT_LT(a.state().tet_awake_count, m->tets.count() / 2);
  const double settled = worst_difference(a.state(), b.state());
  EXPECT_LT(settled, 0.05 * sag);  // held near the plain equilibrium
  // the press reaches the block: it wakes, and ends where the plain run ends
  int least_asleep = asleep_count(a.state());
  for (int i = 0; i < 1600; ++i) {
    ASSERT_TRUE(a.tick()) << a.state().fault.describe(*m);
    ASSERT_TRUE(b.tick()) << b.state().fault.describe(*plain);
    least_asleep = std::min(least_asleep, asleep_count(a.state()));
  }
  EXPECT_LT(least_asleep, 0.5 * m->sleep.eligible_count);  // the load woke most of it
  double moved = 0.0;
  for (int p = 0; p < plain->particle_count(); ++p) moved = std::max(moved, (b.state().x[p] - plain->rest_pos[p]).norm());
  EXPECT_GT(moved, 5e-3);
  EXPECT_LT(worst_difference(a.state(), b.state()), 0.05 * moved);
  EXPECT_GE(asleep_count(a.state()), 0.9 * m->sleep.eligible_count);  // and asleep again at rest
}

TEST(TetSleep, StepAllocatesNothingAndSaveRestoreIsBitIdentical) {
  auto m = test::compile_text(block_yaml(true, true));
  Simulation a(m), b(m), c(m);
  for (int i = 0; i < 1450; ++i) ASSERT_TRUE(a.tick());
  ASSERT_GT(asleep_count(a.state()), 0);
  std::vector<uint8_t> saved;
  a.save(saved);
  // waking and falling asleep again rebuild the held elements: still no allocation
  const long before = test::allocation_count();
  for (int i = 0; i < 600; ++i) ASSERT_TRUE(a.tick());
  EXPECT_EQ(test::allocation_count() - before, 0);
  b.restore(saved);
  for (int i = 0; i < 600; ++i) ASSERT_TRUE(b.tick());
  EXPECT_EQ(a.hash(), b.hash());
  for (int i = 0; i < 2050; ++i) ASSERT_TRUE(c.tick());
  EXPECT_EQ(a.hash(), c.hash());
}

TEST(TetSleep, ADamagedSavedElementListIsRefusedOnRestore) {
  auto m = test::compile_text(block_yaml(true, false));
  Simulation a(m), b(m);
  for (int i = 0; i < 300; ++i) ASSERT_TRUE(a.tick());
  std::vector<uint8_t> saved;
  a.save(saved);
  // the block has no tools: the save ends with tet_order (4-byte indices), tet_awake_count,
  // tet_held_vol and tet_held_f (each array after its 8-byte count)
  const size_t n = m->particle_count(), nn = m->tets.nodes.size(), nt = m->tets.count();
  const size_t first_index = saved.size() - (8 + 24 * n) - (8 + 8 * nn) - 4 - 4 * nt;
  const int32_t bad = 1 << 30;
  std::memcpy(&saved[first_index], &bad, sizeof bad);
  EXPECT_THROW(b.restore(saved), std::runtime_error);
}

TEST(TetSleep, BadKeysAreRefusedWithTheirField) {
  const auto expect_field = test::expect_refused_with_field;
  expect_field(block_yaml(true, false, ", sleep_wake_m_s2: 0"), "solver.sleep_wake_m_s2");
  expect_field(block_yaml(true, false, ", sleep_wake_m_s2: fast"), "solver.sleep_wake_m_s2");
  expect_field(block_yaml(true, false, ", multirate: true"), "solver.sleep");
  std::string maybe = block_yaml(true, false);
  maybe.replace(maybe.find("sleep: true"), 11, "sleep: maybe");
  expect_field(maybe, "solver.sleep");
}

}  // namespace
}  // namespace ps
