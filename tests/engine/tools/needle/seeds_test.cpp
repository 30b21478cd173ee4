// Brachytherapy seeds: deposited at their planned depths while the needle is pulled back,
// embedded in the tissue and carried by it afterwards; planned vs actual reported.
#include <gtest/gtest.h>

#include "engine/tools/needle/needle_output.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps {
namespace {

TEST(Seeds, DepositedWhileRetractingThenCarriedByTheTissue) {
  test::BlockOptions o;
  o.young_kpa = 15;
  o.walls = false;
  // after the needle is out, the block's base is moved 3 mm along x: the tissue carries the seeds
  o.extra_constraints =
      "  - displace: {component: tissue, region: {box: {min_mm: [-100, -100, -25], max_mm: [100, 100, -23]}}, "
      "by_mm: [3, 0, 0], ramp_s: [1.9, 2.1]}\n";
  auto s = test::make_needle_scene(test::block_yaml(
      o, test::vertical_needle("b", 1.3, 0.9, "[[0, 0], [0.8, 17], [1.0, 17], [1.8, 2]]", "      seeds_mm: [15, 11, 7]\n")));
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(s.sim->tick());
  for (const SeedReport& r : s.tool->seeds()) EXPECT_FALSE(r.deposited) << "nothing before retraction";
  for (int i = 0; i < 850; ++i) ASSERT_TRUE(s.sim->tick());
  auto seeds = s.tool->seeds();
  ASSERT_EQ(seeds.size(), 3u);
  for (const SeedReport& r : seeds) {
    EXPECT_TRUE(r.deposited) << r.index;
    EXPECT_TRUE(r.embedded) << r.index;
    // deposited where the tip came back to the planned depth (the tissue was dragged a little)
    EXPECT_LT((r.deposited_at - r.planned).norm(), 2.5e-3) << r.index;
  }
  EXPECT_LT(seeds[0].time, seeds[1].time);
  EXPECT_LT(seeds[1].time, seeds[2].time);
  // nearest particle to each seed now, to compare the seed's motion with the tissue's
  const Model& m = *s.model;
  std::vector<int> near;
  std::vector<Vec3> seed0, part0;
  for (const SeedReport& r : seeds) {
    int best = -1;
    double bd = 1e9;
    for (int p = 0; p < m.particle_count(); ++p)
      if ((s.sim->state().x[p] - r.current).norm() < bd) { bd = (s.sim->state().x[p] - r.current).norm(); best = p; }
    near.push_back(best);
    seed0.push_back(r.current);
    part0.push_back(s.sim->state().x[best]);
  }
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(s.sim->tick());
  seeds = s.tool->seeds();
  for (size_t k = 0; k < seeds.size(); ++k) {
    const Vec3 ds = seeds[k].current - seed0[k];
    const Vec3 dp = s.sim->state().x[near[k]] - part0[k];
    EXPECT_GT(ds.x(), 1.2e-3) << "seed " << k << " moved with the tissue";
    EXPECT_LT((ds - dp).norm(), 0.3e-3) << "seed " << k << " stays attached";
    EXPECT_NEAR(seeds[k].error, (seeds[k].current - seeds[k].planned).norm(), 1e-12);
    EXPECT_GT(seeds[k].error, 1e-3) << "planned vs actual reports the displacement";
  }
  const std::string csv = seeds_csv(*s.tool);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  int seed_events = 0;
  for (const auto& e : s.tool->events().snapshot()) seed_events += e.kind == NeedleEventKind::Seed;
  EXPECT_EQ(seed_events, 3);
}

TEST(Seeds, AStepBackOnTheWayInDepositsNothing) {
  // the needle backs off 1 mm at 8 mm (as when a surface gives way or a neighbour punctures),
  // then goes on to 17 mm and is pulled back: the seeds leave only on the real pull-back, each
  // where the tip returns to its planned depth (the first build dropped them all at the step back)
  test::BlockOptions o;
  o.young_kpa = 15;
  auto s = test::make_needle_scene(test::block_yaml(
      o, test::vertical_needle("b", 1.3, 0.9, "[[0, 0], [0.5, 8], [0.6, 7], [1.1, 17], [1.3, 17], [2.1, 2]]",
                               "      seeds_mm: [15, 11]\n")));
  for (int i = 0; i < 700; ++i) ASSERT_TRUE(s.sim->tick());
  for (const SeedReport& r : s.tool->seeds()) EXPECT_FALSE(r.deposited) << "seed " << r.index << " at the step back";
  for (int i = 0; i < 1400; ++i) ASSERT_TRUE(s.sim->tick());
  for (const SeedReport& r : s.tool->seeds()) {
    EXPECT_TRUE(r.deposited) << r.index;
    EXPECT_GT(r.time, 1.3) << r.index;
    EXPECT_LT((r.deposited_at - r.planned).norm(), 2.5e-3) << r.index;
  }
}

}  // namespace
}  // namespace ps
