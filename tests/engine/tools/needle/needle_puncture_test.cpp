// Puncture of each organ surface met along the path (skin/fat, then the capsule): one event per
// component with its depth and force, and the interior is cut only once its surface is breached.
#include <gtest/gtest.h>

#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps {
namespace {

TEST(NeedlePuncture, EachSurfaceMetIsBreachedOnceInOrder) {
  const std::string y =
      "name: layers\n"
      "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
      "gravity_m_s2: [0, 0, 0]\n"
      "materials:\n"
      "  fat: {young_kpa: 10, density_kg_m3: 950, damping_1_s: 30, k_c_n: 0.3, k_f_n: 0.015}\n"
      "  gland: {young_kpa: 20, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.6, k_f_n: 0.03}\n"
      "components:\n"
      "  - {name: fat, material: fat, spacing_mm: 4, box: {min_mm: [-12, -12, -12], max_mm: [12, 12, 0]}}\n"
      "  - {name: prostate, material: gland, spacing_mm: 4, box: {min_mm: [-12, -12, -36], max_mm: [12, 12, -16]}}\n"
      "links:\n"
      "  - {a: fat, b: prostate, distance_mm: 5}\n"
      "constraints:\n"
      "  - fix: {component: prostate, region: {box: {min_mm: [-100, -100, -37], max_mm: [100, 100, -35]}}}\n"
      "needles:\n"
      "  puncture_n: {fat: 1.5, prostate: 3.0}\n"
      "  instruments:\n"
      "    - {name: n, gauge: 18, length_mm: 100, start_mm: [1.3, 0.9, 1], direction: [0, 0, -1], script: [[0, 0], [1.3, 30]]}\n";
  auto s = test::make_needle_scene(y);
  const int fat = s.model->find_component("fat"), prostate = s.model->find_component("prostate");
  bool cut_prostate_before = false;
  for (int i = 0; i < 1300; ++i) {
    ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
    if (!s.tool->component_entered(0, prostate))
      for (int p : s.tool->cutting_particles(0)) cut_prostate_before |= s.model->component_of[p] == prostate;
  }
  EXPECT_FALSE(cut_prostate_before) << "the gland is not cut through an intact capsule";
  std::vector<NeedleEvent> punct;
  for (const auto& e : s.tool->events().snapshot())
    if (e.kind == NeedleEventKind::Puncture) punct.push_back(e);
  ASSERT_EQ(punct.size(), 2u);
  EXPECT_EQ(punct[0].component, fat);
  EXPECT_EQ(punct[1].component, prostate);
  EXPECT_LT(punct[0].time, punct[1].time);
  EXPECT_LT(punct[0].depth, punct[1].depth);
  EXPECT_GT(punct[1].depth, 16e-3) << "the capsule lies 16 mm below the skin";
  EXPECT_NEAR(punct[0].force, 1.5, 0.05);
  EXPECT_GT(punct[1].force, 3.0) << "capsule threshold plus the cutting and friction in the fat";
  EXPECT_TRUE(s.tool->component_entered(0, fat));
  EXPECT_TRUE(s.tool->component_entered(0, prostate));
}

TEST(NeedlePuncture, AWallModelledAsASurfaceIsPuncturedFromInside) {
  // transrectal biopsy: the needle starts in the lumen of a closed wall (surface-only component)
  // and goes out through it into the gland; the wall is pressed from inside, torn, then rubs
  const std::string y =
      "name: wall\n"
      "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
      "gravity_m_s2: [0, 0, 0]\n"
      "materials:\n"
      "  wall: {young_kpa: 20, density_kg_m3: 1040, damping_1_s: 30, k_c_n: 0.5, k_f_n: 0.02}\n"
      "  gland: {young_kpa: 20, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.6, k_f_n: 0.03}\n"
      "components:\n"
      "  - {name: rectum, material: wall, fill: surface, spacing_mm: 4, box: {min_mm: [-12, -12, -24], max_mm: [12, 12, 0]}}\n"
      "  - {name: prostate, material: gland, spacing_mm: 4, box: {min_mm: [-12, -12, 4], max_mm: [12, 12, 28]}}\n"
      "links:\n"
      "  - {a: rectum, b: prostate, distance_mm: 5}\n"
      "constraints:\n"
      "  - fix: {component: rectum, region: {box: {min_mm: [-100, -100, -25], max_mm: [100, 100, -12]}}}\n"
      "  - fix: {component: prostate, region: {box: {min_mm: [-100, -100, 27], max_mm: [100, 100, 29]}}}\n"
      "needles:\n"
      "  puncture_n: {rectum: 1.2, prostate: 2.0}\n"
      "  instruments:\n"
      "    - {name: b, preset: biopsy_18g, start_mm: [1.3, 0.9, -8], direction: [0, 0, 1], script: [[0, 0], [1.0, 22]]}\n";
  auto s = test::make_needle_scene(y);
  const int rectum = s.model->find_component("rectum"), prostate = s.model->find_component("prostate");
  EXPECT_FALSE(s.tool->component_entered(0, rectum)) << "starting inside a wall's lumen is not being through it";
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
  std::vector<NeedleEvent> punct;
  for (const auto& e : s.tool->events().snapshot())
    if (e.kind == NeedleEventKind::Puncture) punct.push_back(e);
  ASSERT_EQ(punct.size(), 2u);
  EXPECT_EQ(punct[0].component, rectum);
  EXPECT_NEAR(punct[0].force, 1.2, 0.05);
  EXPECT_EQ(punct[1].component, prostate);
  // the torn wall now rubs the shaft: some friction zone holds wall particles
  bool wall_rubs = false;
  for (int j = 0; j < 15; ++j)
    for (int p : s.tool->zone_particles(0, j)) wall_rubs |= s.model->component_of[p] == rectum;
  EXPECT_TRUE(wall_rubs);
}

}  // namespace
}  // namespace ps
