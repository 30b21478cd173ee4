// CLI tests of bad input (issue 9: range checks and size estimates reach the user as exit 2 with
// file:line:field) and of `prostatesim stress` (issue 14: options out of range refused; a quick
// run on a small scene prints its table and exits 0).
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "tests/app/run_cli.h"

namespace ps::test {
namespace {

std::string cube(const std::string& young = "10", const std::string& spacing = "10", const std::string& side = "40") {
  return "name: c\ntime: {dt_ms: 1, substeps: 1, duration_s: 0.01}\nmaterials:\n  soft: {young_kpa: " + young +
         ", density_kg_m3: 1000, damping_1_s: 20}\ncomponents:\n  - name: cube\n    material: soft\n    spacing_mm: " + spacing +
         "\n    box: {min_mm: [0, 0, 0], max_mm: [" + side + ", " + side + ", " + side + "]}\n"
         "constraints:\n  - fix: {component: cube, region: {box: {min_mm: [-1, -1, -1], max_mm: [1000, 1000, 0.5]}}}\n";
}

std::string write(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string p = dir + "/" + name;
  std::ofstream(p) << text;
  return p;
}

TEST(CliBadInput, HugeYoungIsExit2WithFileLineField) {
  const auto d = cli_temp_dir("bad_young").string();
  const auto r = run_cli("simulate " + write(d, "s.yaml", cube("1e30")) + " --out " + d + "/out");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("s.yaml:4: 'materials.soft.young_kpa'"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(d + "/out")) << "nothing may be written on bad input";
}

TEST(CliBadInput, TinySpacingIsRefusedFastNamingTheLimitAndKey) {
  const auto d = cli_temp_dir("bad_spacing").string();
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = run_cli("simulate " + write(d, "s.yaml", cube("10", "0.01", "200")) + " --out " + d + "/out");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("'components[0].spacing_mm'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("over the limit"), std::string::npos) << r.out;
  EXPECT_LT(s, 10.0);
}

TEST(CliStress, OptionsOutOfRangeAreRefused) {
  EXPECT_EQ(run_cli("stress --budget 0").code, 2);
  EXPECT_EQ(run_cli("stress --soak -1").code, 2);
  EXPECT_EQ(run_cli("stress --run 1e9").code, 2);
  const auto r = run_cli("stress /nonexistent/scene.yaml");
  EXPECT_EQ(r.code, 2) << r.out;
}

TEST(CliStress, QuickRunOnACubePrintsTheTableAndHolds) {
  const auto d = cli_temp_dir("stress_cube").string();
  const auto r = run_cli("stress --quick " + write(d, "s.yaml", cube()) + " --json " + d + "/s.json --csv " + d + "/s.csv");
  EXPECT_EQ(r.code, 0) << r.out;
  for (const char* c : {"stable_substep", "stiff_inclusion_1000", "random_impulses", "soak", "needle_1m_s"})
    EXPECT_NE(r.out.find(c), std::string::npos) << c << "\n" << r.out;
  EXPECT_NE(r.out.find("largest stable substep"), std::string::npos) << r.out;
  EXPECT_NE(read_text(d + "/s.json").find("\"status\": \"held\""), std::string::npos);
  EXPECT_NE(read_text(d + "/s.csv").find("scene,case,status"), std::string::npos);
}

}  // namespace
}  // namespace ps::test
