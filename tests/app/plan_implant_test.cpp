// Issue 46: a seed implant that follows its plan. config/brachytherapy_plan.yaml takes its needles
// from config/brachytherapy_plan_145gy.yaml (written by `prostatesim plan`); `prostatesim insert`
// runs them through the physics and metrics.json holds the planned dose (the plan's seeds at their
// planned sites on the organs at rest) beside the achieved (the seeds where the tissue carried
// them, on the organs at the end).
//  * always: the scene's planned indices are the plan file's predicted ones (the same seeds, grid
//    and structures), read after 0.1 s;
//  * PROSTATESIM_SLOW_TESTS=1: the whole implant (20 needles one after another, 133 s simulated,
//    ~90 s of one core): the achieved prostate V100 within 5 percentage points of the plan's, every
//    seed deposited (measured: planned 95.8 %, achieved 92.3 %).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app/run_cli.h"

namespace {

namespace fs = std::filesystem;
const std::string kSource = PROSTATESIM_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool slow_tests() {
  const char* e = std::getenv("PROSTATESIM_SLOW_TESTS");
  return e && *e && std::string(e) != "0";
}

nlohmann::json dosimetry_of(const std::string& name, const std::string& extra) {
  const fs::path out = ps::test::cli_temp_dir("plan_implant_" + name) / "out";
  const auto r = ps::test::run_cli("insert " + kSource + "/config/brachytherapy_plan.yaml " + extra + " --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(read(out / "metrics.json"));
  return j["brachytherapy"]["dosimetry"];
}

TEST(PlanImplant, TheScenesPlannedDoseIsThePlanFilesPrediction) {
  const YAML::Node plan = YAML::LoadFile(kSource + "/config/brachytherapy_plan_145gy.yaml")["plan"];
  const YAML::Node x = plan["predicted"];
  const nlohmann::json d = dosimetry_of("short", "--duration 0.1");
  const nlohmann::json& p = d["planned"];
  EXPECT_EQ(p["seeds"].get<int>(), plan["seeds"].as<int>());
  // the plan file rounds to 4 decimals (fractions) and 0.1 Gy
  EXPECT_NEAR(p["prostate_v100"].get<double>(), x["prostate_v100"].as<double>(), 6e-5);
  EXPECT_NEAR(p["prostate_d90_gy"].get<double>(), x["prostate_d90_gy"].as<double>(), 0.06);
  EXPECT_NEAR(p["urethra_d10_gy"].get<double>(), x["urethra_d10_gy"].as<double>(), 0.06);
  EXPECT_NEAR(p["rectum_d2cc_gy"].get<double>(), x["rectum_d2cc_gy"].as<double>(), 0.06);
  EXPECT_GE(p["prostate_v100"].get<double>(), 0.95) << "the shipped plan meets V100 >= 95 %";
}

TEST(PlanImplant, TheAchievedV100IsWithinFivePointsOfThePlans) {
  if (!slow_tests()) GTEST_SKIP() << "~90 s of one core: set PROSTATESIM_SLOW_TESTS=1";
  const nlohmann::json d = dosimetry_of("full", "");
  const nlohmann::json &p = d["planned"], &a = d["achieved"];
  std::printf("plan-following implant: V100 planned %.2f %%, achieved %.2f %%; D90 %.1f / %.1f Gy; urethra D10 %.1f / %.1f Gy; "
              "rectum D2cc %.1f / %.1f Gy\n",
              100 * p["prostate_v100"].get<double>(), 100 * a["prostate_v100"].get<double>(), p["prostate_d90_gy"].get<double>(),
              a["prostate_d90_gy"].get<double>(), p["urethra_d10_gy"].get<double>(), a["urethra_d10_gy"].get<double>(),
              p["rectum_d2cc_gy"].get<double>(), a["rectum_d2cc_gy"].get<double>());
  EXPECT_EQ(a["seeds"].get<int>(), p["seeds"].get<int>()) << "every planned seed deposited";
  EXPECT_LE(std::abs(a["prostate_v100"].get<double>() - p["prostate_v100"].get<double>()), 0.05);
}

}  // namespace
