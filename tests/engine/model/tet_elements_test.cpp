// Tet-model elements (engine/model/tet_elements.cpp, delaunay.cpp): they tile the component
// (volumes add up to the enclosed volume), are positively oriented and not slivers, none lies
// outside a non-convex component, linked components get elements across their interface, and
// compilation is deterministic.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/model/delaunay.h"
#include "engine/model/tet_elements.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

TEST(Delaunay, LatticeCubeIsTiledWithoutFlatCells) {
  std::vector<Vec3> pts;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) pts.emplace_back(i, j, k);  // co-spherical everywhere
  const auto tets = delaunay_tetrahedra(pts);
  double vol = 0;
  for (const auto& t : tets) {
    const double v = (pts[t[1]] - pts[t[0]]).dot((pts[t[2]] - pts[t[0]]).cross(pts[t[3]] - pts[t[0]])) / 6.0;
    EXPECT_GT(v, 1e-9);
    vol += v;
  }
  EXPECT_NEAR(vol, 27.0, 1e-9);
  EXPECT_EQ(delaunay_tetrahedra(pts), tets);  // deterministic
}

TEST(TetElements, CylinderFillTilesItsVolume) {
  auto m = test::compile_text(
      "name: t\nmaterials: {soft: {young_kpa: 60, model: tet}}\ncomponents:\n"
      "  - {name: c, material: soft, spacing_mm: 6, cylinder: {radius_mm: 12, length_mm: 30}}\n");
  const TetElements& te = m->tets;
  ASSERT_GT(te.count(), 0);
  double vol = 0;
  for (double v : te.vol0) { EXPECT_GT(v, 0.0); vol += v; }
  // the surface encloses this volume; elements dropped as slivers leave a little out
  EXPECT_NEAR(vol, m->surfaces[0].rest_volume, 0.02 * m->surfaces[0].rest_volume);
  EXPECT_LE(vol, m->surfaces[0].rest_volume * (1 + 1e-9));
  for (int p = 0; p < m->particle_count(); ++p) EXPECT_GE(te.node_slot[p], 0) << p;
}

TEST(TetElements, WindingNumberInsideOutside) {
  auto m = test::compile_text(
      "name: t\nmaterials: {soft: {young_kpa: 60, model: tet}}\ncomponents:\n"
      "  - {name: b, material: soft, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [30,30,30]}}\n");
  const auto& f = m->surfaces[0].faces;
  EXPECT_NEAR(winding_number(f, m->rest_pos, Vec3(0.015, 0.015, 0.015)), 1.0, 1e-9);
  EXPECT_NEAR(winding_number(f, m->rest_pos, Vec3(0.045, 0.015, 0.015)), 0.0, 1e-9);
}

TEST(TetElements, LinkedComponentsShareElements) {
  const std::string y =
      "name: t\nmaterials: {soft: {young_kpa: 10, model: tet}}\ncomponents:\n"
      "  - {name: a, material: soft, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [30,30,30]}}\n"
      "  - {name: b, material: soft, spacing_mm: 10, box: {min_mm: [0,0,35], max_mm: [30,30,65]}}\n"
      "links:\n  - {a: a, b: b, distance_mm: 8}\n";
  auto m = test::compile_text(y);
  int across = 0;
  for (int t = 0; t < m->tets.count(); ++t) {
    int in_a = 0;
    for (int i = 0; i < 4; ++i) in_a += m->component_of[m->tets.v[4 * t + i]] == 0;
    across += (in_a > 0 && in_a < 4);
  }
  EXPECT_GT(across, 0);
  // the same two boxes unlinked: none
  auto unlinked = test::compile_text(y.substr(0, y.find("links:")));
  for (int t = 0; t < unlinked->tets.count(); ++t)
    EXPECT_EQ(unlinked->component_of[unlinked->tets.v[4 * t]], unlinked->component_of[unlinked->tets.v[4 * t + 3]]);
}

}  // namespace
}  // namespace ps
