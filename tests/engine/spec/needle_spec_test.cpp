// The `needles:` section: parsing, presets, and bad input -> InputError naming the field.
#include "engine/spec/needle_spec.h"

#include <gtest/gtest.h>

#include "engine/util/error.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps {
namespace {

using test::BlockOptions;
using test::block_yaml;
using test::vertical_needle;

std::string needle_with(const std::string& extra, const std::string& script = "[[0, 0], [1, 10]]") {
  return block_yaml(BlockOptions{}, vertical_needle("n", 1.3, 0.9, script, extra));
}

// Parses (and builds the tool, which checks against the model); returns the error's field.
std::string error_field(const std::string& yaml) {
  try {
    test::make_needle_scene(yaml);
  } catch (const InputError& e) {
    return e.field();
  }
  return "<no error>";
}

TEST(NeedleSpec, ParsesTheSectionInSiUnits) {
  const ScenarioSpec s = parse_scenario_text(
      needle_with("      node_spacing_mm: 1.5\n      mass_g: 5\n      coupling_stiffness_n_mm: 3\n      friction_radius_mm: 3.5\n"
                  "      seeds_mm: [5, 8]\n      static_ratio: 1.2\n"),
      "n.yaml");
  ASSERT_EQ(s.needles.needles.size(), 1u);
  const NeedleSpec& n = s.needles.needles[0];
  EXPECT_EQ(n.name, "n");
  EXPECT_DOUBLE_EQ(n.diameter, 1.27e-3);  // 18G
  EXPECT_DOUBLE_EQ(n.length, 0.1);
  EXPECT_DOUBLE_EQ(n.node_spacing, 1.5e-3);
  EXPECT_DOUBLE_EQ(n.mass, 5e-3);
  EXPECT_DOUBLE_EQ(n.coupling_stiffness, 3000.0);
  EXPECT_DOUBLE_EQ(n.friction_radius, 3.5e-3);
  EXPECT_DOUBLE_EQ(n.static_ratio, 1.2);
  EXPECT_TRUE(n.start.isApprox(Vec3(1.3e-3, 0.9e-3, 1e-3)));
  EXPECT_TRUE(n.direction.isApprox(Vec3(0, 0, -1)));
  ASSERT_EQ(n.script.size(), 2u);
  EXPECT_DOUBLE_EQ(n.script[1].depth, 10e-3);
  ASSERT_EQ(n.seed_depths.size(), 2u);
  EXPECT_DOUBLE_EQ(n.seed_depths[1], 8e-3);
  ASSERT_EQ(s.needles.puncture.size(), 1u);
  EXPECT_EQ(s.needles.puncture[0].first, "tissue");
  EXPECT_DOUBLE_EQ(s.needles.puncture[0].second, 2.45);
}

TEST(NeedleSpec, PresetsAreEighteenGaugeAndKeysOverrideThem) {
  NeedleSpec b, r;
  ASSERT_TRUE(apply_needle_preset("biopsy_18g", b));
  ASSERT_TRUE(apply_needle_preset("brachy_18g", r));
  EXPECT_DOUBLE_EQ(b.diameter, 1.27e-3);
  EXPECT_DOUBLE_EQ(r.diameter, 1.27e-3);
  EXPECT_DOUBLE_EQ(b.length, 0.25);
  EXPECT_DOUBLE_EQ(r.length, 0.20);
  EXPECT_FALSE(apply_needle_preset("sword", b));
  const ScenarioSpec s = parse_scenario_text(
      block_yaml(BlockOptions{}, "    - {name: n, preset: brachy_18g, length_mm: 150, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n"
                                 "    - {name: m, preset: biopsy_18g, start_mm: [5, 0, 1], direction: [0, 0, -1]}\n"),
      "n.yaml");
  EXPECT_DOUBLE_EQ(s.needles.needles[0].length, 0.15);  // a key beats the preset
  EXPECT_DOUBLE_EQ(s.needles.needles[1].length, 0.25);
  EXPECT_NEAR(gauge_diameter(22), 0.718e-3, 1e-9);
  EXPECT_EQ(gauge_diameter(5), 0.0);
}

TEST(NeedleSpec, BadInputNamesTheField) {
  const std::string k = "needles.instruments[0].";
  // length_mm / gauge / node spacing (the vertical_needle helper writes gauge and length first;
  // repeated keys are a YAML error, so these override through other spellings)
  EXPECT_EQ(error_field(block_yaml(BlockOptions{}, "    - {name: n, length_mm: 0, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n")),
            k + "length_mm");
  EXPECT_EQ(error_field(block_yaml(BlockOptions{}, "    - {name: n, length_mm: -20, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n")),
            k + "length_mm");
  EXPECT_EQ(error_field(block_yaml(BlockOptions{}, "    - {name: n, gauge: 0, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n")),
            k + "gauge");
  EXPECT_EQ(error_field(block_yaml(BlockOptions{}, "    - {name: n, gauge: -18, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n")),
            k + "gauge");
  EXPECT_EQ(error_field(block_yaml(BlockOptions{}, "    - {name: n, gauge: 40, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n")),
            k + "gauge");
  EXPECT_EQ(error_field(block_yaml(BlockOptions{}, "    - {name: n, diameter_mm: 0, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n")),
            k + "diameter_mm");
  EXPECT_EQ(error_field(needle_with("      node_spacing_mm: 80\n")), k + "node_spacing_mm");
  // nonsensical zones
  EXPECT_EQ(error_field(needle_with("      friction_radius_mm: 0.1\n")), k + "friction_radius_mm");
  EXPECT_EQ(error_field(needle_with("      cutting_radius_mm: 400\n")), k + "cutting_radius_mm");
  EXPECT_EQ(error_field(needle_with("      friction_radius_mm: -3\n")), k + "friction_radius_mm");
  EXPECT_EQ(error_field(needle_with("      static_ratio: 0.5\n")), k + "static_ratio");
  // seeds beyond the needle or beyond the scripted depth
  EXPECT_EQ(error_field(needle_with("      seeds_mm: [5, 150]\n")), k + "seeds_mm[1]");
  EXPECT_EQ(error_field(needle_with("      seeds_mm: [5, 30]\n")), k + "seeds_mm[1]");
  EXPECT_EQ(error_field(needle_with("      seeds_mm: [0]\n")), k + "seeds_mm[0]");
  // script
  EXPECT_EQ(error_field(needle_with("", "[[0, 0], [0, 10]]")), k + "script[1]");
  EXPECT_EQ(error_field(needle_with("", "[[0, 0], [1, 300]]")), k + "script[1]");
  EXPECT_EQ(error_field(needle_with("", "[[0, 0], [1]]")), k + "script[1]");
  // gun
  EXPECT_EQ(error_field(needle_with("      gun: {fire_s: 1, duration_ms: 500}\n")), k + "gun.duration_ms");
  // a gun without fire_s is armed and fires on a live command only (engine/contract/command.h)
  EXPECT_EQ(error_field(needle_with("      gun: {stroke_mm: 20}\n")), "<no error>");
  EXPECT_EQ(error_field(needle_with("      gun: {fire_s: -1}\n")), k + "gun.fire_s");
  // typos and references
  EXPECT_EQ(error_field(needle_with("      lenght_mm: 100\n")), k + "lenght_mm");
  EXPECT_EQ(error_field(needle_with("      preset: sword\n")), k + "preset");
  EXPECT_EQ(error_field(needle_with("      tumour: [nope]\n")), k + "tumour[0]");
  BlockOptions o;
  o.extra_puncture = ", liver: 2";
  EXPECT_EQ(error_field(block_yaml(o, vertical_needle("n", 0, 0, "[[0, 0]]"))), "needles.puncture_n.liver");
  // direction must be non-zero
  EXPECT_EQ(error_field(block_yaml(BlockOptions{}, "    - {name: n, start_mm: [0, 0, 1], direction: [0, 0, 0]}\n")),
            k + "direction");
}

TEST(NeedleSpec, NeedleOutsideTheSceneIsAnErrorNamingItsStart) {
  // 30 cm to the side of a 24 mm block, pointing away
  try {
    test::make_needle_scene(block_yaml(BlockOptions{}, vertical_needle("far", 300, 0, "[[0, 0], [1, 50]]")));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "needles.instruments[0].start_mm");
    EXPECT_NE(std::string(e.what()).find("outside the scene"), std::string::npos) << e.what();
    EXPECT_GT(e.line(), 0);
  }
  // pointing away from the block
  try {
    test::make_needle_scene(block_yaml(
        BlockOptions{}, "    - {name: up, start_mm: [0, 0, 40], direction: [0, 0, 1], script: [[0, 0], [1, 50]]}\n"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "needles.instruments[0].start_mm");
  }
}

TEST(NeedleSpec, ProgrammaticSpecsAreCheckedToo) {
  NeedleSpec s;
  s.key = "needle";
  s.length = -1;
  EXPECT_THROW(validate_needle_spec(s), InputError);
  s = NeedleSpec{};
  s.key = "needle";
  s.seed_depths = {0.3};
  try {
    validate_needle_spec(s);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "needle.seeds_mm[0]");
  }
}

}  // namespace
}  // namespace ps
