// Scenario keys added for the anatomy: exclude_inside (a fat block around organs), ellipsoid
// regions, tags: and prostate_zones:, with their errors.
#include "engine/scenario/scene_regions.h"

#include <gtest/gtest.h>

#include "engine/mesh/mesh_query.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/util/error.h"

namespace ps {
namespace {

// A 60 mm block of "fat" (10 mm spacing) around a 20 mm "organ" box (5 mm spacing), linked.
std::string block_yaml(const std::string& organ_box = "{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}",
                       const std::string& extra = "", const std::string& fat_extra = "    exclude_inside: [organ]\n") {
  return "name: block\n"
         "gravity_m_s2: [0, 0, 0]\n"
         "materials:\n"
         "  soft: {young_kpa: 3, density_kg_m3: 1000}\n"
         "  organ: {young_kpa: 30, density_kg_m3: 1000, incompressible: true}\n"
         "components:\n"
         "  - name: organ\n"
         "    material: organ\n"
         "    spacing_mm: 5\n"
         "    box: " + organ_box + "\n"
         "  - name: fat\n"
         "    material: soft\n"
         "    spacing_mm: 10\n"
         "    box: {min_mm: [0, 0, 0], max_mm: [60, 60, 60]}\n" +
         fat_extra +
         "links:\n"
         "  - {a: fat, b: organ, distance_mm: 12}\n" +
         extra;
}

std::shared_ptr<const Model> compile(const std::string& yaml) { return compile_scenario(parse_scenario_text(yaml, "t.yaml")); }

std::string error_of(const std::string& yaml) {
  try {
    compile(yaml);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ExcludeInside, LeavesTheOrganEmptyAndItsVolumeOutOfTheFatMass) {
  const auto model = compile(block_yaml());
  const Model& m = *model;
  const Component& fat = m.components[m.find_component("fat")];
  int near_organ = 0;
  for (int p = fat.first_particle; p < fat.first_particle + fat.particle_count; ++p) {
    const Vec3 x = m.rest_pos[p] * 1e3;   // mm
    const bool in = (x.array() > 20 - 4.5 + 1e-6).all() && (x.array() < 40 + 4.5 - 1e-6).all();
    EXPECT_FALSE(in) << "fat particle " << p << " at " << x.transpose();
    near_organ += (x.array() > 10 - 1e-6).all() && (x.array() < 50 + 1e-6).all();
  }
  EXPECT_GT(near_organ, 0);
  double mass = 0.0;
  for (int p = fat.first_particle; p < fat.first_particle + fat.particle_count; ++p) mass += m.mass[p];
  EXPECT_NEAR(mass, 1000.0 * (0.06 * 0.06 * 0.06 - 0.02 * 0.02 * 0.02), 1e-9);   // [kg]
  // without exclusion the fat fills the organ too
  const auto full = compile(block_yaml("{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}", "", ""));
  EXPECT_GT(full->components[full->find_component("fat")].particle_count, fat.particle_count + 8);
}

TEST(ExcludeInside, RefusesOrgansOutsideTheBlockAndBadNames) {
  EXPECT_NE(error_of(block_yaml("{min_mm: [50, 20, 20], max_mm: [70, 40, 40]}")).find("is not inside 'fat'"), std::string::npos);
  EXPECT_NE(error_of(block_yaml("{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}", "", "    exclude_inside: [liver]\n"))
                .find("unknown component 'liver'"),
            std::string::npos);
  EXPECT_NE(error_of(block_yaml("{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}", "", "    exclude_inside: [fat]\n"))
                .find("cannot exclude itself"),
            std::string::npos);
  EXPECT_NE(error_of(block_yaml("{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}", "",
                                "    fill: surface\n    exclude_inside: [organ]\n"))
                .find("only a volumetric component"),
            std::string::npos);
}

TEST(Regions, EllipsoidSelectsItsInside) {
  RegionSpec r;
  r.kind = RegionSpec::Ellipsoid;
  r.center = Vec3(0.01, 0, 0);
  r.radii = Vec3(0.01, 0.005, 0.002);
  EXPECT_TRUE(r.contains(Vec3(0.019, 0, 0)));
  EXPECT_FALSE(r.contains(Vec3(0.021, 0, 0)));
  EXPECT_TRUE(r.contains(Vec3(0.01, 0.0049, 0)));
  EXPECT_FALSE(r.contains(Vec3(0.01, 0.0, 0.0021)));
  const std::string bad = block_yaml("{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}",
                                     "overrides:\n  - {component: organ, region: {ellipsoid: {center_mm: [30, 30, 30], radii_mm: [5, 0, 5]}}, young_kpa: 9}\n");
  EXPECT_NE(error_of(bad).find("t.yaml:"), std::string::npos);
  EXPECT_NE(error_of(bad).find("radii_mm"), std::string::npos);
}

TEST(Tags, NamedRegionsBecomeParticleBits) {
  const auto model = compile(block_yaml(
      "{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}",
      "tags:\n"
      "  - {name: lesion, component: organ, region: {ellipsoid: {center_mm: [30, 30, 30], radii_mm: [6, 6, 6]}}}\n"
      "  - {name: floor, component: fat, region: {half_space: {point_mm: [0, 0, 1], normal: [0, 0, -1]}}}\n"
      "overrides:\n"
      "  - {component: organ, region: {ellipsoid: {center_mm: [30, 30, 30], radii_mm: [6, 6, 6]}}, young_kpa: 90}\n"));
  const Model& m = *model;
  ASSERT_EQ(m.tag_names, (std::vector<std::string>{"lesion", "floor"}));
  int lesion = 0, floor = 0;
  for (int p = 0; p < m.particle_count(); ++p) {
    const bool l = m.particle_tags[p] & 1, f = m.particle_tags[p] >> 1 & 1;
    lesion += l;
    floor += f;
    if (l) {
      EXPECT_EQ(m.components[m.component_of[p]].name, "organ");
      EXPECT_LE((m.rest_pos[p] - Vec3(0.03, 0.03, 0.03)).norm(), 0.006 + 1e-12);
      EXPECT_GT(m.k_e[p], m.k_e[m.components[0].first_particle]);   // the override hit the same particles
    }
    if (f) EXPECT_LE(m.rest_pos[p].z(), 0.001);
  }
  EXPECT_GE(lesion, 7);
  EXPECT_GE(floor, 36);
  // a scene without tags keeps no tag arrays
  EXPECT_TRUE(compile(block_yaml())->particle_tags.empty());
}

TEST(Tags, Errors) {
  const std::string organ = "{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}";
  EXPECT_NE(error_of(block_yaml(organ, "tags:\n  - {name: a, component: organ, region: all}\n  - {name: a, component: fat, region: all}\n"))
                .find("duplicate tag name 'a'"),
            std::string::npos);
  EXPECT_NE(error_of(block_yaml(organ, "tags:\n  - {name: a, component: liver, region: all}\n")).find("unknown component 'liver'"),
            std::string::npos);
  EXPECT_NE(error_of(block_yaml(organ, "tags:\n  - {name: a, component: organ, region: {sphere: {center_mm: [0, 0, 0], radius_mm: 1}}}\n"))
                .find("selects no particle"),
            std::string::npos);
  EXPECT_NE(error_of(block_yaml(organ, "prostate_zones: {component: organ}\ntags:\n  - {name: base, component: organ, region: all}\n"))
                .find("prostate zone name"),
            std::string::npos);
  EXPECT_NE(error_of(block_yaml(organ, "prostate_zones: {component: gland}\n")).find("unknown component 'gland'"), std::string::npos);
}

TEST(Tags, ZonesOnABoxGland) {
  const auto model = compile(block_yaml("{min_mm: [20, 20, 20], max_mm: [40, 40, 40]}", "prostate_zones: {component: organ, peripheral_depth_mm: 4}\n"));
  const Model& m = *model;
  ASSERT_EQ(m.tag_names.size(), 10u);
  const Component& organ = m.components[m.find_component("organ")];
  const int apex = m.find_tag("apex"), base = m.find_tag("base"), tz = m.find_tag("transition");
  for (int p = 0; p < m.particle_count(); ++p) {
    const uint64_t t = m.particle_tags[p];
    if (m.component_of[p] != m.find_component("organ")) {
      EXPECT_EQ(t, 0u);
      continue;
    }
    EXPECT_EQ(__builtin_popcountll(t), 4);   // level, side, medial/lateral, zone
    if (m.rest_pos[p].z() < 0.026) EXPECT_TRUE(t >> apex & 1);
    if (m.rest_pos[p].z() > 0.034) EXPECT_TRUE(t >> base & 1);
    if (m.on_surface[p]) EXPECT_FALSE(t >> tz & 1);   // the capsule is never transition zone
  }
  EXPECT_GT(organ.particle_count, 100);
}

}  // namespace
}  // namespace ps
