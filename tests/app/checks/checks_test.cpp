// The validation and stress cases called in process, through the library the `validate` and
// `stress` commands use (app/checks/), not through the executable.
#include <gtest/gtest.h>

#include <string>

#include "app/checks/stress.h"
#include "app/checks/validation.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"

namespace ps::app {
namespace {

TEST(ChecksLibrary, TheTg43CaseRunsInProcessAndMatchesTheConsensusTables) {
  const ValidationCase* tg43 = nullptr;
  for (const ValidationCase& c : validation_cases())
    if (c.name == "tg43") tg43 = &c;
  ASSERT_NE(tg43, nullptr) << "no tg43 case in validation_cases()";
  const std::vector<ValidationRow> rows = tg43->run(PROSTATESIM_SOURCE_DIR, PROSTATESIM_SHARED_DATA);
  ASSERT_GT(rows.size(), 10u);
  for (const ValidationRow& r : rows) EXPECT_TRUE(r.pass()) << r.metric << ": " << r.value << " vs " << r.reference;
}

TEST(ChecksLibrary, RandomLiveCommandsOnTheProbeSceneHold) {
  const ScenarioSpec spec = parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml");
  StressOptions opt;
  opt.cases = {"random_commands"};
  opt.run_s = 0.05;
  const std::vector<StressResult> out = run_stress_cases(spec, compile_scenario(spec), opt, [](const std::string&) {});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].status, "held") << out[0].held;
  EXPECT_FALSE(out[0].failed());
}

}  // namespace
}  // namespace ps::app
