// Biopsy gun fire (~22 mm in 15 ms) stays stable, and the core lists what lies in the notch.
#include <gtest/gtest.h>

#include "engine/tools/needle_output.h"
#include "tests/engine/tools/needle_scenes.h"

namespace ps {
namespace {

std::string biopsy_yaml() {
  return "name: biopsy\n"
         "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
         "gravity_m_s2: [0, 0, 0]\n"
         "materials:\n"
         "  gland: {young_kpa: 15, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.5, k_f_n: 0.025}\n"
         "  lesion: {young_kpa: 30, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.8, k_f_n: 0.04}\n"
         "components:\n"
         "  - {name: prostate, material: gland, spacing_mm: 4, box: {min_mm: [-12, -12, -16], max_mm: [12, 12, 0]}}\n"
         "  - {name: tumour, material: lesion, spacing_mm: 4, box: {min_mm: [-12, -12, -40], max_mm: [12, 12, -20]}}\n"
         "links:\n"
         "  - {a: prostate, b: tumour, distance_mm: 5}\n"
         "constraints:\n"
         "  - fix: {component: tumour, region: {box: {min_mm: [-100, -100, -41], max_mm: [100, 100, -39]}}}\n"
         "needles:\n"
         "  puncture_n: {prostate: 2.5}\n"
         "  instruments:\n"
         "    - name: gun\n"
         "      preset: biopsy_18g\n"
         "      start_mm: [1.3, 0.9, 1]\n"
         "      direction: [0, 0, -1]\n"
         "      script: [[0, 0], [0.4, 8]]\n"
         "      gun: {fire_s: 0.5, stroke_mm: 22, duration_ms: 15}\n";
}

TEST(Biopsy, GunFireIsFastStableAndTheCoreHoldsTheTumour) {
  auto s = test::make_needle_scene(biopsy_yaml());
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(s.sim->tick());
  const double tip0 = s.tool->readout(0).tip.z();
  double vmax_tissue = 0, needle_speed = 0;
  double t_stroke = -1;
  for (int i = 0; i < 100; ++i) {
    ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
    vmax_tissue = std::max(vmax_tissue, max_speed(s.sim->state()));
    needle_speed = std::max(needle_speed, s.tool->readout(0).velocity.norm());
    if (t_stroke < 0 && tip0 - s.tool->readout(0).tip.z() > 20e-3) t_stroke = s.sim->state().time - 0.5;
  }
  ASSERT_GT(t_stroke, 0.0) << "the needle advanced 20 mm";
  EXPECT_LT(t_stroke, 0.05) << "well under 0.1 s";
  EXPECT_GT(needle_speed, 1.0);
  EXPECT_LT(vmax_tissue, 10.0) << "fast, but no blow-up";
  const CoreReport core = s.tool->core(0);
  ASSERT_TRUE(core.taken);
  EXPECT_GT(core.time, 0.515);
  int prostate = 0, tumour = 0;
  for (const auto& [name, n] : core.per_component) (name == "prostate" ? prostate : tumour) += n;
  EXPECT_GT(prostate, 0);
  EXPECT_GT(tumour, 0);
  EXPECT_EQ(core.tumour_particles, tumour) << "'tumour' is recognised by its name";
  // notch 5..23 mm behind a tip ~29 mm deep: tumour from 20 mm down is ~6 mm of the notch
  EXPECT_GT(core.tumour_length, 3e-3);
  EXPECT_LT(core.tumour_length, 12e-3);
  EXPECT_DOUBLE_EQ(core.notch_length, 18e-3);
  int cores = 0;
  for (const auto& e : s.tool->events().snapshot()) cores += e.kind == NeedleEventKind::Core;
  EXPECT_EQ(cores, 1);
  EXPECT_NE(cores_csv(*s.tool).find("gun,1,"), std::string::npos);
}

TEST(Biopsy, TumourGivenAsAParticleTagIsMeasuredInTheCore) {
  // one gland block with a tagged lesion 2.5..9.5 mm deep; the core reports tags (zones, lesion)
  std::string y = biopsy_yaml();
  y.replace(y.find("  - {name: tumour,"), y.find("links:") - y.find("  - {name: tumour,"), "");
  y.replace(y.find("links:"), y.find("constraints:") - y.find("links:"),
            "tags:\n  - {name: lesion, component: prostate, region: {box: {min_mm: [-12, -12, -9.5], max_mm: [12, 12, -2.5]}}}\n");
  y.replace(y.find("component: tumour, region: {box: {min_mm: [-100, -100, -41], max_mm: [100, 100, -39]}}"),
            std::string("component: tumour, region: {box: {min_mm: [-100, -100, -41], max_mm: [100, 100, -39]}}").size(),
            "component: prostate, region: {box: {min_mm: [-100, -100, -17], max_mm: [100, 100, -15]}}");
  y.replace(y.find("script: [[0, 0], [0.4, 8]]"), std::string("script: [[0, 0], [0.4, 8]]").size(), "script: [[0, 0], [0.4, 2]]");
  y.replace(y.find("stroke_mm: 22"), std::string("stroke_mm: 22").size(), "stroke_mm: 14");
  auto s = test::make_needle_scene(y);
  ASSERT_GE(s.model->find_tag("lesion"), 0);
  for (int i = 0; i < 560; ++i) ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
  const CoreReport core = s.tool->core(0);
  ASSERT_TRUE(core.taken);
  int lesion = 0;
  for (const auto& [name, n] : core.per_tag) lesion += name == "lesion" ? n : 0;
  EXPECT_GT(lesion, 0);
  EXPECT_EQ(core.tumour_particles, lesion) << "'lesion' tags count as tumour";
  EXPECT_GT(core.tumour_length, 2e-3);
  EXPECT_LT(core.tumour_length, 10e-3);
}

TEST(Biopsy, InteractiveFireAdvancesFromTheCommandedPose) {
  std::string y = biopsy_yaml();
  y.replace(y.find("fire_s: 0.5"), std::string("fire_s: 0.5").size(), "fire_s: 100");
  auto s = test::make_needle_scene(y);
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(s.sim->tick());
  const Vec3 tip = s.tool->readout(0).tip;
  s.tool->command(0, tip, Vec3(0, 0, -1));  // the hand holds the gun where it is
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(s.sim->tick());
  EXPECT_FALSE(s.tool->core(0).taken);
  s.tool->fire(0, s.sim->state().time);
  for (int i = 0; i < 60; ++i) ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
  EXPECT_NEAR(tip.z() - s.tool->readout(0).tip.z(), 22e-3, 1.5e-3);
  EXPECT_TRUE(s.tool->core(0).taken);
}

}  // namespace
}  // namespace ps
