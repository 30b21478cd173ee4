// Displacement measurements (engine/tools/probe/displacement_field.h): zones by superior position,
// statistics of known fields, and the per-particle CSV.
#include "engine/tools/probe/displacement_field.h"

#include <gtest/gtest.h>

#include <sstream>

#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

TEST(DisplacementField, ZonesAreThirdsAlongTheSuperiorDirection) {
  // 40 mm cube at 10 mm spacing: z layers 0, 10, 20, 30, 40 mm -> apex {0, 10}, mid {20}, base {30, 40}
  auto m = test::compile_text(test::cube_yaml(40, 10, false, false));
  const std::vector<int> z = si_zones(*m, 0, m->rest_pos, Vec3::UnitZ());
  for (int p = 0; p < m->particle_count(); ++p) {
    const double h = m->rest_pos[p].z();
    EXPECT_EQ(z[p], h < 0.015 ? 0 : (h < 0.025 ? 1 : 2)) << "z = " << h;
  }
  // the direction decides which end is the base
  const std::vector<int> flipped = si_zones(*m, 0, m->rest_pos, -Vec3::UnitZ());
  for (int p = 0; p < m->particle_count(); ++p) EXPECT_EQ(flipped[p], 2 - z[p]);
}

TEST(DisplacementField, StatisticsOfKnownFields) {
  auto m = test::compile_text(test::cube_yaml(40, 10, false, false));
  const int n = m->particle_count();
  std::vector<Vec3> x = m->rest_pos;
  // rigid translation: mean = max = |t| everywhere, mean vector t
  const Vec3 t(0.001, -0.002, 0.002);
  for (Vec3& p : x) p += t;
  DisplacementStats d = displacement_stats(*m, 0, m->rest_pos, x, Vec3::UnitZ());
  EXPECT_EQ(d.all.count, n);
  EXPECT_EQ(d.apex.count + d.mid.count + d.base.count, n);
  EXPECT_NEAR(d.all.mean, t.norm(), 1e-15);
  EXPECT_NEAR(d.all.max, t.norm(), 1e-15);
  EXPECT_NEAR((d.base.mean_vec - t).norm(), 0.0, 1e-15);
  // compression toward the floor, u_z = -0.1 z: zero at the apex end, largest at the base
  for (int p = 0; p < n; ++p) x[p] = m->rest_pos[p] - Vec3(0, 0, 0.1 * m->rest_pos[p].z());
  d = displacement_stats(*m, 0, m->rest_pos, x, Vec3::UnitZ());
  EXPECT_NEAR(d.all.max, 0.004, 1e-15);
  EXPECT_NEAR(d.apex.mean, 0.0005, 1e-15);  // layers 0 and 10 mm
  EXPECT_NEAR(d.mid.mean, 0.002, 1e-15);
  EXPECT_NEAR(d.base.mean, 0.0035, 1e-15);
  EXPECT_NEAR(d.base.mean_vec.z(), -0.0035, 1e-15);
}

TEST(DisplacementField, CsvHasOneRowPerParticleInMillimetres) {
  auto m = test::compile_text(test::cube_yaml(20, 10, false, false));
  std::vector<Vec3> x = m->rest_pos;
  x[5] += Vec3(0.003, 0, -0.004);
  const std::string csv = displacement_csv(*m, -1, m->rest_pos, x, Vec3::UnitZ());
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "id,component,zone,x0_mm,y0_mm,z0_mm,x_mm,y_mm,z_mm,ux_mm,uy_mm,uz_mm,u_mm");
  int rows = 0;
  std::string row5;
  while (std::getline(in, line)) {
    if (rows == 5) row5 = line;
    ++rows;
  }
  EXPECT_EQ(rows, m->particle_count());
  EXPECT_NE(row5.find("5,cube,"), std::string::npos) << row5;
  EXPECT_NE(row5.find(",3.000000,0.000000,-4.000000,5.000000"), std::string::npos) << row5;
}

}  // namespace
}  // namespace ps
