// The CSV files of `prostatesim dose`: seeds (x_mm,y_mm,z_mm,axis_x,axis_y,axis_z,
// air_kerma_strength_U) and points (x_mm,y_mm,z_mm). A header names the columns (any order, extra
// columns ignored); "#" lines and blank lines are skipped. Bad input throws InputError naming the
// file, the line and the field: a missing column, a number that does not parse or is not finite,
// a zero axis, a strength that is not positive.
#pragma once
#include <string>
#include <vector>

#include "engine/dosimetry/seed.h"

namespace ps::dosimetry {

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;           // 1-based file line of each row
};

CsvTable parse_csv(const std::string& text, const std::string& file);
std::vector<Seed> parse_seeds_csv(const std::string& text, const std::string& file);
std::vector<Vec3> parse_points_csv(const std::string& text, const std::string& file);

}  // namespace ps::dosimetry
