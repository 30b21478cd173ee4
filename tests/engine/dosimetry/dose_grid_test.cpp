#include "engine/dosimetry/dose_grid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ps::dosimetry {
namespace {

std::vector<Seed> some_seeds() {
  std::vector<Seed> s;
  for (int i = 0; i < 6; ++i) {
    Seed q;
    q.centre_mm = Vec3(-8.0 + 3.3 * i, 2.0 * std::sin(i), 5.0 * i - 10.0);
    q.axis = Vec3(0.1 * i, 0.0, 1.0).normalized();
    q.strength_u = 0.4 + 0.05 * i;
    s.push_back(q);
  }
  return s;
}

TEST(DoseGrid, GridAroundCoversTheBoxAndMargin) {
  const GridSpec g = grid_around(Vec3(-10, -5, 0), Vec3(10, 5, 30), 10.0, 1.0);
  EXPECT_EQ(g.nx, 40);
  EXPECT_EQ(g.ny, 30);
  EXPECT_EQ(g.nz, 50);
  EXPECT_NEAR(g.centre_mm(0, 0, 0).x(), -19.5, 1e-12);
  EXPECT_NEAR(g.voxel_cc(), 1e-3, 1e-15);
}

TEST(DoseGrid, KernelMatchesTheFormalismBeyondTwoMillimetres) {
  const SourceModel& s = *find_source_model("I125_6711");
  const DoseKernel k(s);
  Seed q;
  q.strength_u = 1.0;
  double worst = 0.0;
  for (double z = 0.0; z <= 60.0; z += 1.7)
    for (double r = 0.0; r <= 60.0; r += 2.3) {
      if (std::hypot(z, r) < 2.0) continue;
      const double exact = seed_total_dose_gy(s, q, Vec3(r, 0, z));
      worst = std::max(worst, std::abs(k.gy_per_u(z, r) / exact - 1.0));
    }
  EXPECT_LT(worst, 0.01);
}

TEST(DoseGrid, IncrementalUpdatesEqualAFreshComputation) {
  const SourceModel& s = *find_source_model("I125_6711");
  const GridSpec g = grid_around(Vec3(-15, -10, -15), Vec3(15, 10, 15), 5.0, 2.0);
  std::vector<Seed> seeds = some_seeds();
  DoseAccumulator live(s, g);
  std::vector<Seed> partial(seeds.begin(), seeds.begin() + 3);
  EXPECT_EQ(live.update(partial), 3);
  EXPECT_EQ(live.update(partial), 0);               // nothing moved
  EXPECT_EQ(live.update(seeds), 3);                 // three new ones
  seeds[1].centre_mm += Vec3(0.1, 0, 0);            // within tolerance: kept
  EXPECT_EQ(live.update(seeds), 0);
  seeds[1].centre_mm += Vec3(1.0, 0, 0);            // moved: out and in again
  EXPECT_EQ(live.update(seeds), 2);
  DoseAccumulator fresh(s, g);
  fresh.rebuild(seeds);
  double worst = 0.0, peak = 0.0;
  for (size_t i = 0; i < g.size(); ++i) {
    worst = std::max(worst, static_cast<double>(std::abs(live.dose_gy()[i] - fresh.dose_gy()[i])));
    peak = std::max(peak, static_cast<double>(fresh.dose_gy()[i]));
  }
  EXPECT_LT(worst, 1e-5 * peak);
  // and the grid holds the sum of the seeds' doses at its voxel centres (kernel accuracy)
  // (a voxel more than 2 mm from every seed: closer in, the kernel's bilinear steps are coarse)
  const Vec3 p = g.centre_mm(14, 10, 3);
  for (const Seed& q : seeds) ASSERT_GT((q.centre_mm - p).norm(), 2.0);
  EXPECT_NEAR(fresh.dose_gy()[g.index(14, 10, 3)] / total_dose_gy(s, seeds, p), 1.0, 0.01);
  std::vector<Seed> fewer(seeds.begin(), seeds.begin() + 4);
  EXPECT_EQ(live.update(fewer), 2);
  fresh.rebuild(fewer);
  EXPECT_NEAR(live.dose_gy()[g.index(10, 7, 12)], fresh.dose_gy()[g.index(10, 7, 12)], 1e-4);
}

}  // namespace
}  // namespace ps::dosimetry

namespace ps::dosimetry {
namespace {

TEST(DoseGrid, MovedSeedsBeyondTheBudgetFollowInLaterUpdates) {
  const SourceModel& s = *find_source_model("I125_6711");
  const GridSpec g = grid_around(Vec3(-15, -10, -15), Vec3(15, 10, 15), 5.0, 2.0);
  std::vector<Seed> seeds = some_seeds();
  DoseAccumulator live(s, g);
  live.update(seeds);
  for (Seed& q : seeds) q.centre_mm += Vec3(0, 1.0, 0);   // the gland pushed as a whole
  EXPECT_EQ(live.update(seeds, 0.25, 2), 4);              // two seeds re-added
  EXPECT_EQ(live.lagging(), 4);
  EXPECT_EQ(live.update(seeds, 0.25, 2), 4);
  EXPECT_EQ(live.update(seeds, 0.25, 2), 4);
  EXPECT_EQ(live.lagging(), 0);
  EXPECT_EQ(live.update(seeds, 0.25, 2), 0);
  DoseAccumulator fresh(s, g);
  fresh.rebuild(seeds);
  for (size_t i = 0; i < g.size(); i += 97) EXPECT_NEAR(live.dose_gy()[i], fresh.dose_gy()[i], 1e-4 * (1.0 + fresh.dose_gy()[i]));
}

}  // namespace
}  // namespace ps::dosimetry
