#include "engine/dosimetry/dose_csv.h"

#include <gtest/gtest.h>

#include "engine/util/error.h"

namespace ps::dosimetry {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_seeds_csv(text, "seeds.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(DoseCsv, ReadsSeedsInAnyColumnOrder) {
  const auto s = parse_seeds_csv(
      "# two seeds\naxis_x,axis_y,axis_z,x_mm,y_mm,z_mm,air_kerma_strength_U\n0,0,2,1,2,3,0.5\n\n1,0,0,4,5,6,0.4\n", "s.csv");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].centre_mm, Vec3(1, 2, 3));
  EXPECT_EQ(s[0].axis, Vec3(0, 0, 1));
  EXPECT_DOUBLE_EQ(s[1].strength_u, 0.4);
}

TEST(DoseCsv, BadSeedFilesNameFileLineAndField) {
  const std::string head = "x_mm,y_mm,z_mm,axis_x,axis_y,axis_z,air_kerma_strength_U\n";
  EXPECT_EQ(error_of("x_mm,y_mm,z_mm,axis_x,axis_y,axis_z\n1,2,3,0,0,1\n"),
            "seeds.csv:1: 'air_kerma_strength_U': missing column (the header must name it)");
  EXPECT_EQ(error_of(head + "1,2,3,0,0,1,0\n"), "seeds.csv:2: 'air_kerma_strength_U': must be positive (got 0)");
  EXPECT_EQ(error_of(head + "1,2,3,0,0,1,0.5\n1,2,3,0,0,1,-1\n"),
            "seeds.csv:3: 'air_kerma_strength_U': must be positive (got -1)");
  EXPECT_EQ(error_of(head + "1,abc,3,0,0,1,0.5\n"), "seeds.csv:2: 'y_mm': 'abc' is not a finite number");
  EXPECT_EQ(error_of(head + "1,2,3,0,0,1\n"), "seeds.csv:2: 'air_kerma_strength_U': missing value");
  EXPECT_EQ(error_of(head + "1,2,3,0,0,0,0.5\n"), "seeds.csv:2: 'axis_x': the seed axis is zero (give its needle's direction)");
  EXPECT_EQ(error_of(head + "1,2,nan,0,0,1,0.5\n"), "seeds.csv:2: 'z_mm': 'nan' is not a finite number");
  EXPECT_EQ(error_of(""), "seeds.csv: 'header': no header line (the file is empty)");
}

TEST(DoseCsv, ReadsPoints) {
  const auto p = parse_points_csv("x_mm,y_mm,z_mm\n1,2,3\n-4,5.5,6\n", "p.csv");
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1], Vec3(-4, 5.5, 6));
  EXPECT_THROW(parse_points_csv("x_mm,z_mm\n1,2\n", "p.csv"), InputError);
}

}  // namespace
}  // namespace ps::dosimetry
