// Bad scenario input: one error naming file:line and the key.
#include "engine/scenario/parse_yaml.h"

#include <gtest/gtest.h>

#include "engine/scenario/compile.h"
#include "engine/util/error.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

struct BadCase {
  std::string what, yaml, key;
  int line;
};

std::string base_with(const std::string& materials, const std::string& component_extra) {
  return "name: t\n"
         "materials:\n" + materials +
         "components:\n"
         "  - name: cube\n"
         "    material: soft\n"
         "    spacing_mm: 10\n"
         "    box: {min_mm: [0, 0, 0], max_mm: [40, 40, 40]}\n" + component_extra;
}

TEST(ParseYaml, GoodScenarioParsesInSI) {
  const ScenarioSpec s = parse_scenario_text(test::cube_yaml(40, 10, true), "good.yaml");
  EXPECT_EQ(s.components.size(), 1u);
  EXPECT_DOUBLE_EQ(s.components[0].spacing, 0.01);
  EXPECT_DOUBLE_EQ(*s.materials[0].young, 10e3);
  EXPECT_DOUBLE_EQ(s.dt, 1e-3);
  EXPECT_TRUE(s.materials[0].incompressible);
}

TEST(ParseYaml, BadInputNamesFileLineAndKey) {
  const std::string soft = "  soft: {young_kpa: 10}\n";
  const std::vector<BadCase> cases = {
      {"unknown key", base_with(soft, "    colour: red\n"), "components[0].colour", 9},
      {"negative modulus", base_with("  soft: {young_kpa: -3}\n", ""), "materials.soft.young_kpa", 3},
      {"negative spacing", "name: t\nmaterials:\n  soft: {young_kpa: 1}\ncomponents:\n  - name: c\n    material: soft\n    spacing_mm: -1\n    box: {min_mm: [0,0,0], max_mm: [1,1,1]}\n", "components[0].spacing_mm", 7},
      {"wrong type", base_with("  soft: {young_kpa: soft}\n", ""), "materials.soft.young_kpa", 3},
      {"missing key", "name: t\nmaterials:\n  soft: {young_kpa: 1}\ncomponents:\n  - name: c\n    material: soft\n    box: {min_mm: [0,0,0], max_mm: [1,1,1]}\n", "components[0].spacing_mm", 5},
      {"unknown material", base_with("  hard: {young_kpa: 10}\n", ""), "components[0].material", 5},
      {"bad vector", base_with(soft, "") + "gravity_m_s2: [0, 1]\n", "gravity_m_s2", 9},
      {"empty components", "name: t\nmaterials:\n  soft: {young_kpa: 1}\ncomponents: []\n", "components", 4},
      {"unknown top-level", base_with(soft, "") + "gravitee: 3\n", "gravitee", 9},
      {"triplets zero", base_with(soft, "") + "solver: {triplets: 0}\n", "solver.triplets", 9},
      {"triplets word", base_with(soft, "") + "solver: {triplets: some}\n", "solver.triplets", 9},
      {"mass scaling not a bool", base_with(soft, "") + "solver: {mass_scaling: 3}\n", "solver.mass_scaling", 9},
  };
  for (const auto& c : cases) {
    try {
      parse_scenario_text(c.yaml, "scene.yaml");
      ADD_FAILURE() << c.what << ": accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "scene.yaml") << c.what;
      EXPECT_EQ(e.field(), c.key) << c.what << ": " << e.what();
      EXPECT_EQ(e.line(), c.line) << c.what << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("scene.yaml:" + std::to_string(c.line)), std::string::npos) << e.what();
    }
  }
}

TEST(ParseYaml, EmptySelectionIsAnError) {
  const std::string y = test::cube_yaml(40, 10, false, false) +
                        "constraints:\n  - fix: {component: cube, region: {sphere: {center_mm: [500, 0, 0], radius_mm: 1}}}\n";
  try {
    compile_scenario(parse_scenario_text(y, "sel.yaml"));
    FAIL() << "empty selection accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "constraints[0].region");
    EXPECT_GT(e.line(), 0);
  }
}

TEST(ParseYaml, UnreadableFile) {
  EXPECT_THROW(parse_scenario_file("/nonexistent/dir/scene.yaml"), InputError);
}

TEST(ParseYaml, SyntaxErrorHasLine) {
  try {
    parse_scenario_text("name: t\nmaterials: {soft: [\n", "syn.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_GT(e.line(), 0);
  }
}

}  // namespace
}  // namespace ps
