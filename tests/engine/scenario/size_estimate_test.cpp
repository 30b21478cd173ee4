// Tests for engine/scenario/size_estimate.cpp and the range checks of the scenario reader
// (engine/spec/yaml_reader.h, parse_yaml.cpp) and of compile (substep count): every absurd
// value is refused with file:line:field before anything large is allocated.
#include "engine/scenario/size_estimate.h"

#include <gtest/gtest.h>

#include <regex>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/util/error.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

std::string replace(std::string s, const std::string& a, const std::string& b) {
  const size_t i = s.find(a);
  EXPECT_NE(i, std::string::npos) << a;
  if (i != std::string::npos) s.replace(i, a.size(), b);
  return s;
}

// The InputError thrown by parse + compile of `yaml` (fails the test when none is thrown).
InputError input_error_of(const std::string& yaml) {
  try {
    compile_scenario(parse_scenario_text(yaml, "scene.yaml"));
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << yaml;
  return InputError("", 0, "", "");
}

TEST(SizeEstimate, BoxEstimateMatchesTheLattice) {
  const ScenarioSpec s = parse_scenario_text(test::cube_yaml(40, 10), "cube.yaml");
  const SizeEstimate e = estimate_component_size(s.components[0], s.file);
  const auto m = compile_scenario(s);
  EXPECT_EQ(e.particles, m->particle_count());  // 5 x 5 x 5 lattice, exact for a box
}

TEST(SizeEstimate, TinySpacingIsRefusedBeforeAllocatingAndNamesTheKey) {
  // 0.05 mm in a 200 mm box: 6.4e10 particles. Must throw fast, without allocating gigabytes.
  const std::string yaml = replace(test::cube_yaml(200, 10), "spacing_mm: 10.000000", "spacing_mm: 0.05");
  const InputError e = input_error_of(yaml);
  EXPECT_EQ(e.field(), "components[0].spacing_mm");
  EXPECT_EQ(e.line(), 7);  // the component's "- name: cube" line
  const std::string msg = e.what();
  EXPECT_NE(msg.find("over the limit"), std::string::npos) << msg;
  EXPECT_NE(msg.find("raise its spacing_mm to at least"), std::string::npos) << msg;
  // The spacing it proposes does fit: re-run with it.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(msg, m, std::regex("at least ([0-9.e+-]+)"))) << msg;
  const ScenarioSpec fixed = parse_scenario_text(replace(yaml, "spacing_mm: 0.05", "spacing_mm: " + m[1].str()), "s.yaml");
  EXPECT_NO_THROW(check_scenario_size(fixed));
}

TEST(SizeEstimate, LimitsAreParameters) {
  const ScenarioSpec s = parse_scenario_text(test::cube_yaml(40, 10), "cube.yaml");
  ScenarioLimits small;
  small.max_particles = 100;  // the cube has 125
  EXPECT_THROW(check_scenario_size(s, small), InputError);
  small.max_particles = 1e6;
  small.max_bytes = 1000;  // memory limit alone
  EXPECT_THROW(check_scenario_size(s, small), InputError);
  EXPECT_NO_THROW(check_scenario_size(s));
}

TEST(ScenarioRanges, AbsurdValuesNameFileLineAndKey) {
  struct Case {
    std::string from, to, field;
  };
  const std::vector<Case> cases = {
      {"young_kpa: 10", "young_kpa: 1e30", "materials.soft.young_kpa"},
      {"young_kpa: 10", "young_kpa: 1e-9", "materials.soft.young_kpa"},
      {"young_kpa: 10", "young_kpa: .inf", "materials.soft.young_kpa"},
      {"young_kpa: 10", "young_kpa: .nan", "materials.soft.young_kpa"},
      {"density_kg_m3: 1000", "density_kg_m3: 1e7", "materials.soft.density_kg_m3"},
      {"dt_ms: 1", "dt_ms: 1e-9", "time.dt_ms"},
      {"dt_ms: 1", "dt_ms: 5000", "time.dt_ms"},
      {"duration_s: 1", "duration_s: 1e8", "time.duration_s"},
      {"substeps: 1", "substeps: 1e12", "time.substeps"},
      {"gravity_m_s2: [0, 0, -9.81]", "gravity_m_s2: [0, 0, -1e5]", "gravity_m_s2"},
      {"spacing_mm: 10.000000", "spacing_mm: 0.001", "components[0].spacing_mm"},
      {"max_mm: [40.000000", "max_mm: [1e12", "components[0].box.max_mm"},
  };
  for (const Case& c : cases) {
    const InputError e = input_error_of(replace(test::cube_yaml(40, 10), c.from, c.to));
    EXPECT_EQ(e.field(), c.field) << c.to << ": " << e.what();
    EXPECT_GT(e.line(), 0) << c.to;
    EXPECT_EQ(e.file(), "scene.yaml");
  }
}

TEST(ScenarioRanges, StiffButAllowedYoungIsRefusedByTheSubstepLimitNotOverflowed) {
  // 1e8 kPa (harder than bone) passes the range check but needs ~1e5+ substeps per 1 ms tick:
  // compile must refuse it, not overflow the substep count to -2147483648.
  const InputError e = input_error_of(replace(replace(test::cube_yaml(40, 10), "young_kpa: 10", "young_kpa: 1e9"), "dt_ms: 1", "dt_ms: 100"));
  EXPECT_EQ(e.field(), "materials.soft.young_kpa") << e.what();
  EXPECT_NE(std::string(e.what()).find("substeps"), std::string::npos) << e.what();
}

TEST(ScenarioRanges, StiffWithinLimitCompilesWithPositiveSubsteps) {
  const auto m = test::compile_text(replace(test::cube_yaml(40, 10), "young_kpa: 10", "young_kpa: 1e5"));
  EXPECT_GT(m->substeps, 1);
  EXPECT_LE(m->substeps, kMaxSubstepsPerTick);
}

}  // namespace
}  // namespace ps
