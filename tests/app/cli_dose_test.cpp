// `prostatesim dose`, `plan` and `validate tg43` as a user runs them: outputs, exit codes, one
// error line naming file, line and field for bad input, nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "tests/app/run_cli.h"

namespace {

namespace fs = std::filesystem;
using Result = ps::test::CliResult;
Result run(const std::string& args) { return ps::test::run_cli(args); }
const std::string kSource = PROSTATESIM_SOURCE_DIR;
const std::string kHead = "x_mm,y_mm,z_mm,axis_x,axis_y,axis_z,air_kerma_strength_U\n";

struct DoseFiles {
  fs::path dir, seeds, points, out;
};

DoseFiles dose_files(const std::string& name, const std::string& seeds) {
  DoseFiles f;
  f.dir = ps::test::cli_temp_dir("dose_" + name);
  f.seeds = f.dir / "seeds.csv";
  f.points = f.dir / "points.csv";
  f.out = f.dir / "dose.csv";
  std::ofstream(f.seeds) << seeds;
  std::ofstream(f.points) << "x_mm,y_mm,z_mm\n10,0,0\n0,0,10\n";
  return f;
}

std::string dose_args(const DoseFiles& f, const std::string& isotope = "I125_6711") {
  return "dose --isotope " + isotope + " --seeds " + f.seeds.string() + " --points " + f.points.string() + " --out " + f.out.string();
}

TEST(CliDose, WritesTheTotalDoseAtThePoints) {
  const DoseFiles f = dose_files("ok", kHead + "0,0,0,0,0,1,0.5\n");
  const Result r = run(dose_args(f));
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(f.out);
  std::string head, a, b;
  std::getline(in, head);
  std::getline(in, a);
  std::getline(in, b);
  EXPECT_EQ(head, "x_mm,y_mm,z_mm,dose_gy");
  // 0.5 U at 1 cm on the transverse axis: 0.965 x 0.5 x 59.4 d x 24 / ln 2 / 100 = 9.92 Gy
  EXPECT_NEAR(std::stod(a.substr(a.rfind(',') + 1)), 9.923, 0.01) << a;
  EXPECT_LT(std::stod(b.substr(b.rfind(',') + 1)), 0.45 * 9.923) << b;  // along the axis
}

TEST(CliDose, BadInputExits2WithOneLineAndWritesNothing) {
  struct Case {
    std::string name, seeds, isotope, expect;
  };
  const Case cases[] = {
      {"isotope", kHead + "0,0,0,0,0,1,0.5\n", "I125_9999", "'--isotope': unknown seed model 'I125_9999'"},
      {"strength", kHead + "0,0,0,0,0,1,0.5\n1,0,0,0,0,1,-0.2\n", "I125_6711", "seeds.csv:3: 'air_kerma_strength_U': must be positive"},
      {"column", "x_mm,y_mm,z_mm,axis_x,axis_y,axis_z\n0,0,0,0,0,1\n", "I125_6711", "seeds.csv:1: 'air_kerma_strength_U': missing column"},
  };
  for (const Case& c : cases) {
    const DoseFiles f = dose_files(c.name, c.seeds);
    const Result r = run(dose_args(f, c.isotope));
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.name << ": " << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << c.name << ": one error line: " << r.out;
    EXPECT_FALSE(fs::exists(f.out)) << c.name;
  }
}

TEST(CliDose, ValidateTg43Passes) {
  const Result r = run("validate tg43");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("phi_an at 1.0 cm"), std::string::npos) << r.out;
}

TEST(CliDose, PlanRejectsANonPositiveStrength) {
  const fs::path dir = ps::test::cli_temp_dir("plan_bad");
  Result r = run("plan " + kSource + "/config/brachytherapy.yaml --strength-u 0 --out " + (dir / "p.yaml").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("'--strength-u': must be positive"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "p.yaml"));
}

// Issue 46 item 2: the default anatomy's plan at 145 Gy meets all four constraints (simulated
// annealing, engine/dosimetry/plan_annealing.h), and the plan file reads back as the scene's
// needles.
TEST(CliDose, PlanOnTheDefaultAnatomyMeetsEveryConstraint) {
  const fs::path dir = ps::test::cli_temp_dir("plan_ok");
  const fs::path out = dir / "plan.yaml";
  const Result r = run("plan " + kSource + "/config/brachytherapy.yaml --prescription-gy 145 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.find("NOT MET"), std::string::npos) << r.out;
  for (const char* c : {"prostate V100 >= 95 %", "prostate D90 >= 100 %", "prostate D90 <= 120 %", "urethra D10 < 150 %",
                        "rectum D2cc < prescription"})
    EXPECT_NE(r.out.find(c), std::string::npos) << c << "\n" << r.out;
  ASSERT_TRUE(fs::exists(out));
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("pass: true"), std::string::npos);
  EXPECT_EQ(text.find("pass: false"), std::string::npos);
  // the same input, the same plan (a fixed random stream)
  const fs::path again = dir / "again.yaml";
  ASSERT_EQ(run("plan " + kSource + "/config/brachytherapy.yaml --prescription-gy 145 --out " + again.string()).code, 0);
  std::ifstream in2(again);
  const std::string text2((std::istreambuf_iterator<char>(in2)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, text2);
}

// Seeds of 0.05 U cannot cover the gland however many are loaded: exit 1 naming the constraint,
// nothing written.
TEST(CliDose, PlanThatCannotMeetItsConstraintsExits1NamingIt) {
  const fs::path dir = ps::test::cli_temp_dir("plan_infeasible");
  const Result r = run("plan " + kSource + "/config/brachytherapy.yaml --strength-u 0.05 --out " + (dir / "p.yaml").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("the plan cannot meet 'prostate V100 >= 95 %'"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "p.yaml"));
}

}  // namespace
