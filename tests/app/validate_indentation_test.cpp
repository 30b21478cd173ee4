// The local-load validation cases (app/checks/validate_indentation.cpp) as CI runs them: the reduced
// version at the scene spacing only (10 mm; `prostatesim validate punch_halfspace
// sphere_indentation` runs 10 and 5 mm from the command line). The field is compared with the
// CalculiX solution kept in docs/reference/, so this fails when the tissue model loses accuracy.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/app/run_cli.h"

namespace ps {
namespace {

namespace fs = std::filesystem;
const std::string kSource = PROSTATESIM_SOURCE_DIR;

TEST(ValidateIndentation, TetModelFieldWithinFivePercentAtTheSceneSpacing) {
  const fs::path json = test::cli_temp_dir("indent") / "rows.json";
  const auto r = test::run_cli("validate punch_halfspace sphere_indentation --spacings-mm 10 --root " + kSource +
                               " --json " + json.string());
  EXPECT_EQ(r.code, 0) << r.out;
  std::ifstream in(json);
  const auto rows = nlohmann::json::parse(in);
  int fields = 0;
  for (const auto& row : rows)
    if (row["metric"] == "field_rms_rel@10mm") {
      ++fields;
      EXPECT_LE(row["value"].get<double>(), 0.05) << row["case"];
    }
  EXPECT_EQ(fields, 2);  // punch and sphere
}

TEST(ValidateIndentation, SpacingOffTheFemGridIsBadInput) {
  const auto r = test::run_cli("validate punch_halfspace --spacings-mm 7 --root " + kSource);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("multiple of 5"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ps
