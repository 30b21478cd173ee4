// The prostatesim command as a user runs it: outputs, exit codes, bad input handling.
#include <gtest/gtest.h>

#include "tests/app/run_cli.h"
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace {

namespace fs = std::filesystem;

using Result = ps::test::CliResult;
Result run(const std::string& args) { return ps::test::run_cli(args); }

fs::path temp_dir(const std::string& name) { return ps::test::cli_temp_dir("cli_" + name); }
std::string read(const fs::path& p) { return ps::test::read_text(p); }

const std::string kSource = PROSTATESIM_SOURCE_DIR;

TEST(Cli, SimulateWritesParticlesSummaryAndSurfaces) {
  const fs::path out = temp_dir("sim") / "run";
  const Result r = run("simulate " + kSource + "/config/demo_cube.yaml --duration 0.2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string csv = read(out / "particles.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "id,component,x0_mm,y0_mm,z0_mm,x_mm,y_mm,z_mm");
  const auto j = nlohmann::json::parse(read(out / "summary.json"));
  for (const char* k : {"steps", "sim_time_s", "wall_time_s", "kinetic_energy_J", "max_speed_m_s", "volume_error", "warnings"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_NEAR(j["sim_time_s"].get<double>(), 0.2, 1e-9);
  EXPECT_LE(j["volume_error"]["block"].get<double>(), 1e-10);
  EXPECT_TRUE(fs::exists(out / "block.obj"));
}

TEST(Cli, UntilRestStopsEarly) {
  const fs::path out = temp_dir("rest") / "run";
  const Result r = run("simulate " + kSource + "/config/demo_cube.yaml --until-rest --duration 30 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(read(out / "summary.json"));
  EXPECT_LT(j["sim_time_s"].get<double>(), 30.0);
  EXPECT_LT(j["kinetic_energy_J"].get<double>(), 1e-7);
}

TEST(Cli, BadScenarioExits2NamingFileLineKeyAndWritesNothing) {
  const fs::path dir = temp_dir("bad");
  const fs::path scen = dir / "bad.yaml";
  std::ofstream(scen) << "name: bad\nmaterials:\n  soft: {young_kpa: -5}\ncomponents:\n"
                         "  - {name: c, material: soft, spacing_mm: 5, box: {min_mm: [0,0,0], max_mm: [10,10,10]}}\n";
  const fs::path out = dir / "out";
  const Result r = run("simulate " + scen.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("bad.yaml:3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("young_kpa"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one error line: " << r.out;
}

TEST(Cli, MissingFileAndBadOptionExit2) {
  EXPECT_EQ(run("simulate /nonexistent/x.yaml --out /tmp/never_written").code, 2);
  EXPECT_FALSE(fs::exists("/tmp/never_written"));
  EXPECT_EQ(run("simulate --duration -3 x.yaml").code, 2);
  EXPECT_EQ(run("no-such-command").code, 2);
}

// Numbers on the command line get the scenario's own bounds: unbounded, `--duration 1e300` would
// overflow the tick count and "succeed" with 0 steps, `--factor 1e-300` would run forever, and a
// bound printed as DBL_MAX would read as 309 digits.
TEST(Cli, OutOfRangeNumbersExit2NamingTheOptionAndItsBounds) {
  const fs::path out = temp_dir("range");
  const std::string scen = kSource + "/config/demo_cube.yaml";
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"simulate " + scen + " --out " + out.string() + " --duration 1e300", "--duration: must be in (0, 1e+06] s, got 1e300"},
      {"simulate " + scen + " --out " + out.string() + " --duration nan", "--duration: must be in (0, 1e+06] s, got nan"},
      {"simulate " + scen + " --out " + out.string() + " --duration 0", "--duration: must be in (0, 1e+06] s, got 0"},
      {"simulate " + scen + " --out " + out.string() + " --duration abc", "--duration: expected a number, got 'abc'"},
      {"insert " + scen + " --out " + out.string() + " --duration inf", "--duration: must be in (0, 1e+06] s, got inf"},
      {"run " + scen + " --headless --factor 1e-300", "--factor: must be in [0.001, 100], got 1e-300"},
      {"run " + scen + " --headless --duration 2e6", "--duration: must be in (0, 1e+06] s, got 2e6"},
      {"replay " + scen + " --script " + kSource + "/config/scripts/biopsy.yaml --duration -1", "--duration: must be in (0, 1e+06] s, got -1"},
  };
  for (const Case& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_LT(r.out.size(), 400u) << c.args << "\n" << r.out;  // one short message
  }
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_FALSE(fs::exists(out / "particles.csv"));
}

// An output path that cannot be written is bad input, found before any work: exit 2 naming the
// option, not an internal error after a whole bench (~20 s) or stress run.
TEST(Cli, OutputPathsThatCannotBeWrittenExit2NamingTheOptionBeforeAnyRun) {
  const fs::path out = temp_dir("outputs");
  const std::string missing = (out / "no_such_folder" / "x.json").string();
  std::ofstream(out / "a_file") << "x";
  const std::string file = (out / "a_file").string();
  const std::string root = " --root " + kSource;
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"bench --quick --json " + missing + root, "'--json': cannot write: the folder"},
      {"bench --quick --json " + out.string() + root, "'--json': is a folder"},
      {"bench --quick --out " + file + root, "'--out': exists and is not a folder"},
      {"stress " + kSource + "/config/validation/cube_bonded.yaml --quick --cases soak --json " + missing, "'--json': cannot write"},
      {"stress " + kSource + "/config/validation/cube_bonded.yaml --quick --cases soak --csv " + missing, "'--csv': cannot write"},
      {"validate cube_bonded --json " + missing + root, "'--json': cannot write"},
      {"validate probe_push --out " + file + root, "'--out': exists and is not a folder"},
      {"simulate " + kSource + "/config/demo_cube.yaml --out " + file, "'--out': exists and is not a folder"},
      {"insert " + kSource + "/config/biopsy.yaml --out " + file, "'--out': exists and is not a folder"},
      {"ultrasound " + kSource + "/config/biopsy.yaml --out " + file, "'--out': exists and is not a folder"},
      {"make-anatomy --out " + file, "'--out': exists and is not a folder"},
  };
  for (const Case& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_EQ(r.out.find("internal error"), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_LT(r.out.size(), 400u) << c.args << "\n" << r.out;  // one message, no run's output before it
  }
  EXPECT_FALSE(fs::exists(out / "no_such_folder"));
}

TEST(Cli, BlowUpExits3NamingParticleAndTime) {
  const fs::path dir = temp_dir("blow");
  const fs::path scen = dir / "blow.yaml";
  // the paper's literal redistribution with a stiff raw k_e grows an oscillation at any dt
  std::ofstream(scen) << "name: blow\nsolver: {redistribution: linear}\ntime: {dt_ms: 1, duration_s: 1}\n"
                         "materials:\n  soft: {k_e_n_m: 1.0e6, damping_1_s: 0}\ncomponents:\n"
                         "  - {name: cube, material: soft, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n"
                         "constraints:\n  - fix: {component: cube, region: {box: {min_mm: [-1,-1,-1], max_mm: [41,41,0.5]}}}\n";
  const fs::path out = dir / "out";
  const Result r = run("simulate " + scen.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("particle"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("t="), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out / "particles.csv"));
  const auto j = nlohmann::json::parse(read(out / "summary.json"));
  EXPECT_TRUE(j.contains("fault"));
}

TEST(Cli, CheckPrintsCountsAndStableDt) {
  const Result r = run("check " + kSource + "/config/demo_cube.yaml");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("block"), std::string::npos);
  EXPECT_NE(r.out.find("largest stable substep"), std::string::npos);
  // 16 hex digits of engine/scenario/model_hash.h, the same on a second compile of the same file.
  const size_t at = r.out.find("model hash ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string hash = r.out.substr(at + 11, 16);
  EXPECT_EQ(hash.find_first_not_of("0123456789abcdef"), std::string::npos) << hash;
  const Result again = run("check " + kSource + "/config/demo_cube.yaml");
  EXPECT_NE(again.out.find("model hash " + hash), std::string::npos) << again.out;
}

TEST(Cli, ValidateJsonRowsHaveExactlyFiveKeysAndExitMatchesStatus) {
  const fs::path json = temp_dir("val") / "rows.json";
  const Result r = run("validate cube_frictionless --root " + kSource + " --json " + json.string());
  ASSERT_TRUE(r.code == 0 || r.code == 1) << r.out;
  const auto rows = nlohmann::json::parse(read(json));
  ASSERT_GE(rows.size(), 1u);
  for (const auto& row : rows) {
    EXPECT_EQ(row.size(), 5u);
    for (const char* k : {"case", "metric", "value", "reference", "unit"}) EXPECT_TRUE(row.contains(k)) << k;
  }
  EXPECT_EQ(rows[0]["metric"], "bulge_mm");
  EXPECT_NEAR(rows[0]["reference"].get<double>(), 2.762, 5e-4);
  EXPECT_EQ(r.code == 0, r.out.find("all within tolerance") != std::string::npos) << r.out;
  EXPECT_EQ(run("validate no_such_case").code, 2);
}

}  // namespace
