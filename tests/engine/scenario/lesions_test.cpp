// Lesions placed per case from a seed (`lesions:`): the same seed gives the same case, another
// seed another one; every lesion lies in the zone asked for, a diameter from the others; bad
// input names file:line.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/util/error.h"

namespace ps {
namespace {

std::string biopsy_with(const std::string& lesions) {
  std::ifstream in(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str() + lesions;
}

// rest centroid of each lesion_k tag
std::vector<Vec3> lesion_centres(const Model& m, int count) {
  std::vector<Vec3> out;
  for (int k = 1; k <= count; ++k) {
    const int t = m.find_tag("lesion_" + std::to_string(k));
    EXPECT_GE(t, 0) << k;
    Vec3 sum = Vec3::Zero();
    int n = 0;
    for (int p = 0; p < m.particle_count(); ++p)
      if (t >= 0 && (m.particle_tags[p] >> t & 1u)) { sum += m.rest_pos[p]; ++n; }
    EXPECT_GT(n, 0) << k;
    out.push_back(n ? Vec3(sum / n) : Vec3::Zero());
  }
  return out;
}

TEST(Lesions, PlacedFromASeedInTheirZone) {
  const std::string base = "lesions: {count: 3, seed: 7, zone: peripheral, diameter_mm: 10}\n";
  const std::string path = std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml";  // meshes relative to config/
  auto a = compile_scenario(parse_scenario_text(biopsy_with(base), path));
  auto b = compile_scenario(parse_scenario_text(biopsy_with(base), path));
  auto c = compile_scenario(parse_scenario_text(biopsy_with("lesions: {count: 3, seed: 8, zone: peripheral, diameter_mm: 10}\n"), path));
  EXPECT_EQ(a->particle_tags, b->particle_tags) << "same seed, same case";
  const auto ca = lesion_centres(*a, 3), cc = lesion_centres(*c, 3);
  double moved = 0.0;
  for (int k = 0; k < 3; ++k) moved += (ca[k] - cc[k]).norm();
  EXPECT_GT(moved, 5e-3) << "another seed, another case";
  const int pz = a->find_tag("peripheral");
  for (int k = 1; k <= 3; ++k) {
    const int t = a->find_tag("lesion_" + std::to_string(k));
    int in_zone = 0, n = 0;
    for (int p = 0; p < a->particle_count(); ++p)
      if (a->particle_tags[p] >> t & 1u) { ++n; in_zone += a->particle_tags[p] >> pz & 1u; }
    EXPECT_GE(in_zone * 2, n) << "lesion_" << k << " centred in the peripheral zone";
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < i; ++j) EXPECT_GE((ca[i] - ca[j]).norm(), 5e-3) << i << " " << j;
}

TEST(Lesions, WithoutZonesIsAnError) {
  const std::string y = "name: box\ntime: {dt_ms: 1}\nmaterials:\n  m: {young_kpa: 10, density_kg_m3: 1000}\ncomponents:\n"
                        "  - {name: prostate, material: m, spacing_mm: 4, box: {min_mm: [0, 0, 0], max_mm: [20, 20, 20]}}\n"
                        "lesions: {count: 2, seed: 1}\n";
  try {
    parse_scenario_text(y, "box.yaml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 7);
    EXPECT_EQ(e.field(), "lesions");
  }
}

}  // namespace
}  // namespace ps
