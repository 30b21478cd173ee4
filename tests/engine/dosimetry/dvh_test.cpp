#include "engine/dosimetry/dvh.h"

#include <gtest/gtest.h>

#include "engine/dosimetry/organ_mask.h"

namespace ps::dosimetry {
namespace {

// A closed axis-aligned box as 12 outward triangles.
void box(const Vec3& lo, const Vec3& hi, std::vector<Vec3>& v, std::vector<std::array<int, 3>>& f) {
  v.clear();
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  f = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
       {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
}

TEST(Dvh, IndicesOfAKnownDistribution) {
  // 100 voxels with doses 1..100 Gy
  std::vector<float> d;
  for (int i = 1; i <= 100; ++i) d.push_back(static_cast<float>(i));
  std::vector<uint8_t> m(100, kProstate);
  const auto p = structure_doses(d, m, kProstate);
  EXPECT_DOUBLE_EQ(dose_to_fraction(p, 0.90), 11.0);   // the hottest 90 voxels: 11..100
  EXPECT_DOUBLE_EQ(dose_to_fraction(p, 0.10), 91.0);
  EXPECT_DOUBLE_EQ(fraction_at_least(p, 50.0), 0.51);
  EXPECT_DOUBLE_EQ(fraction_at_least(p, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(fraction_at_least(p, 101.0), 0.0);
  EXPECT_DOUBLE_EQ(dose_to_volume(p, 0.002, 0.001), 99.0);  // hottest 2 voxels of 1 mm^3
}

TEST(Dvh, BoxFillCountsTheVoxelsInside) {
  const GridSpec g = grid_around(Vec3(0, 0, 0), Vec3(20, 20, 20), 0.0, 1.0);
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  box(Vec3(3.2, 4.1, 5.3), Vec3(13.2, 9.1, 17.3), v, f);  // 10 x 5 x 12 mm
  std::vector<uint8_t> m;
  fill_closed_surface(g, v, f, kProstate, m);
  size_t n = 0;
  for (uint8_t b : m) n += (b & kProstate) ? 1 : 0;
  EXPECT_EQ(n, 10u * 5u * 12u);
  fill_tube(g, {Vec3(10, 10, 2), Vec3(10, 10, 18)}, 2.0, kUrethra, m);
  size_t u = 0;
  for (uint8_t b : m) u += (b & kUrethra) ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(u), 3.14159 * 4 * 16, 0.15 * 3.14159 * 4 * 16);
}

TEST(Dvh, IndicesFromAGridAndMask) {
  const GridSpec g = grid_around(Vec3(0, 0, 0), Vec3(10, 10, 10), 0.0, 1.0);
  std::vector<float> d(g.size());
  std::vector<uint8_t> m(g.size(), 0);
  for (size_t i = 0; i < d.size(); ++i) {
    d[i] = static_cast<float>(i % 200);  // 0..199 Gy
    m[i] = (i < 500) ? kProstate : kRectum;
  }
  const DosimetryIndices x = dosimetry_indices(g, d, m, 145.0, 3);
  EXPECT_NEAR(x.prostate_cc, 0.5, 1e-12);
  EXPECT_NEAR(x.rectum_cc, 0.5, 1e-12);
  EXPECT_NEAR(x.prostate_v100, fraction_at_least(structure_doses(d, m, kProstate), 145.0), 1e-12);
  // a rectum smaller than 2 cc: D2cc is its least dose
  EXPECT_DOUBLE_EQ(x.rectum_d2cc_gy, structure_doses(d, m, kRectum).back());
  const DvhCurve c = dvh_curve(d, m, 145.0, 10);
  ASSERT_EQ(c.dose_gy.size(), 11u);
  EXPECT_DOUBLE_EQ(c.prostate.front(), 1.0);
  for (size_t i = 1; i < c.prostate.size(); ++i) EXPECT_LE(c.prostate[i], c.prostate[i - 1]);
}

}  // namespace
}  // namespace ps::dosimetry
