#include "engine/dosimetry/tg43.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/dosimetry/seed.h"
#include "engine/dosimetry/tg43_check.h"

namespace ps::dosimetry {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Tg43, KnowsTheTwoModelsAndNoOther) {
  ASSERT_NE(find_source_model("I125_6711"), nullptr);
  ASSERT_NE(find_source_model("Pd103_200"), nullptr);
  EXPECT_EQ(find_source_model("I125_6702"), nullptr);
  EXPECT_EQ(source_model_names(), "I125_6711, Pd103_200");
}

TEST(Tg43, ReferencePointGivesTheDoseRateConstant) {
  for (const char* n : {"I125_6711", "Pd103_200"}) {
    const SourceModel& s = *find_source_model(n);
    EXPECT_NEAR(dose_rate_per_u(s, 1.0, 0.5 * kPi), s.lambda_cgy_h_u, 1e-12) << n;
  }
}

TEST(Tg43, LineSourceGeometryTendsToInverseSquare) {
  // far from a 3 mm line the geometry function is 1/r^2 (to (L/r)^2 / 12 relative)
  EXPECT_NEAR(geometry_function(5.0, 0.5 * kPi, 0.3) * 25.0, 1.0, 1e-3);
  EXPECT_NEAR(geometry_function(5.0, 0.0, 0.3) * 25.0, 1.0, 1e-3);
  // on the transverse axis: beta / (L r) with beta = 2 atan(L / 2r)
  EXPECT_NEAR(geometry_function(1.0, 0.5 * kPi, 0.3), 2.0 * std::atan(0.15) / 0.3, 1e-12);
  // symmetric about 90 deg
  EXPECT_NEAR(geometry_function(2.0, 0.3, 0.3), geometry_function(2.0, kPi - 0.3, 0.3), 1e-12);
}

TEST(Tg43, TablesAreReproducedAtTheirNodes) {
  const SourceModel& s = *find_source_model("I125_6711");
  for (size_t i = 0; i < s.g_r_cm.size(); ++i) EXPECT_DOUBLE_EQ(radial_dose(s, s.g_r_cm[i]), s.g[i]);
  EXPECT_DOUBLE_EQ(anisotropy(s, 2.0, 20.0), 0.727);
  EXPECT_NEAR(anisotropy(s, 1.5, 20.0), 0.5 * (0.705 + 0.727), 1e-12);
  EXPECT_NEAR(anisotropy(s, 1.0, 15.0), 0.5 * (0.537 + 0.705), 1e-12);
  // beyond 10 cm g_L falls log-linearly; beyond 5 cm F continues the last two radii
  EXPECT_NEAR(radial_dose(s, 11.0), 0.0803 * (0.0803 / 0.109), 1e-9);
  EXPECT_NEAR(anisotropy(s, 6.0, 0.0), 0.550 + (0.550 - 0.520), 1e-12);
}

TEST(Tg43, PermanentImplantDoseOfOneSeed) {
  // 0.5 U of I-125 at 1 cm on the transverse axis: 0.965 x 0.5 cGy/h x 59.4 d x 24 / ln 2 / 100
  const SourceModel& s = *find_source_model("I125_6711");
  Seed q;
  q.strength_u = 0.5;
  const double expect = 0.965 * 0.5 * 59.4 * 24.0 / std::log(2.0) / 100.0;
  EXPECT_NEAR(seed_total_dose_gy(s, q, Vec3(10, 0, 0)), expect, 1e-9);
  EXPECT_NEAR(expect, 9.92, 0.01);
  // the axis matters: the same distance along the axis gets F(1 cm, 0) ~ 0.37 of it
  EXPECT_LT(seed_total_dose_gy(s, q, Vec3(0, 0, 10)), 0.45 * expect);
  q.axis = Vec3(1, 0, 0);
  EXPECT_LT(seed_total_dose_gy(s, q, Vec3(10, 0, 0)), 0.45 * expect);
}

TEST(Tg43, AgreesWithTheAlongAwayTableWithin2Percent) {
  const auto rows = check_6711_along_away();
  ASSERT_EQ(rows.size(), 86u);  // the table's points at 0.5 cm <= r <= 7 cm
  for (const auto& c : rows) EXPECT_NEAR(c.value / c.reference, 1.0, c.tolerance_rel) << c.metric;
}

TEST(Tg43, AgreesWithTheConsensusOneDimensionalAnisotropyFactor) {
  const auto rows = check_6711_phi_an();
  ASSERT_EQ(rows.size(), 6u);
  for (const auto& c : rows) EXPECT_NEAR(c.value / c.reference, 1.0, c.tolerance_rel) << c.metric;
}

}  // namespace
}  // namespace ps::dosimetry
