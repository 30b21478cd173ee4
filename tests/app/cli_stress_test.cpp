// CLI tests of bad input (issue 9: range checks and size estimates reach the user as exit 2 with
// file:line:field) and of `prostatesim stress` (issue 14: options out of range refused; a quick
// run on a small scene prints its table and exits 0).
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "tests/app/run_cli.h"
#include "tests/time_budget.h"

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
  EXPECT_LT(s, ps::test::time_budget(10.0));
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

std::string loop_script(const std::string& d) {
  return write(d, "loop.yaml", R"(scenario: probe_pelvis_box
duration_s: 0.1
timeline:
  - {t: 0.0, probe: {insertion_mm: 53}, over_s: 0.04}
  - {t: 0.02, fill_rate: bladder, ml_s: 50}
  - {t: 0.05, fill_rate: bladder, ml_s: -50}
  - {t: 0.06, probe: {insertion_mm: 50}, over_s: 0.03}
  - {t: 0.08, fill_rate: bladder, ml_s: 0}
)");
}

// The CI-sized soak through the CLI: the probe and filling validation scene with a 0.1 s script
// looped three times (the one-hour soak of the default scenes is the same command with --soak 3600).
TEST(CliStress, SoakLoopsTheScriptAndWritesItsDriftFigures) {
  const auto d = cli_temp_dir("stress_soak").string();
  const std::string script = loop_script(d);
  const std::string scene = std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml";
  const auto r = run_cli("stress " + scene + " --cases soak --soak 0.3 --script " + script + " --json " + d + "/s.json");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("looping its script"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3 cycles of 0.1 s"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("stable_substep"), std::string::npos) << "--cases soak runs the soak only\n" << r.out;
  const std::string j = read_text(d + "/s.json");
  EXPECT_NE(j.find("\"cycles\": 3"), std::string::npos) << j;
  EXPECT_NE(j.find("\"commands_refused\": 0"), std::string::npos) << j;
  for (const char* k : {"peak_kinetic_j", "worst_volume_drift", "cycle_drift_max_mm", "min_margin_mm", "end_volume_drift_bladder"})
    EXPECT_NE(j.find(k), std::string::npos) << k << "\n" << j;
}

// the value of the first line "key ..." of a text (a checkpoint's embedded state header)
std::string value_of(const std::string& text, const std::string& key) {
  const size_t p = text.find("\n" + key + " ");
  if (p == std::string::npos) return "";
  const size_t b = p + key.size() + 2;
  return text.substr(b, text.find('\n', b) - b);
}

// A soak longer than a sitting goes on from its checkpoint: stopped at 0.15 s (mid-cycle) and
// resumed to 0.3 s, it ends in the same state, bit for bit, with the same figures as one run.
TEST(CliStress, ASoakResumedFromItsCheckpointEndsWhereARunStraightThroughEnds) {
  const auto d = cli_temp_dir("stress_soak_resume").string();
  const std::string script = loop_script(d);
  const std::string scene = std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml";
  const std::string base = "stress " + scene + " --cases soak --script " + script;
  auto r = run_cli(base + " --soak 0.3 --checkpoint " + d + "/a.ckpt --json " + d + "/a.json");
  ASSERT_EQ(r.code, 0) << r.out;
  r = run_cli(base + " --soak 0.15 --checkpoint " + d + "/b.ckpt");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string half = read_text(d + "/b.ckpt");
  EXPECT_EQ(value_of(half, "tick"), "150") << "the checkpoint at the soak's end";
  r = run_cli(base + " --soak 0.3 --resume " + d + "/b.ckpt --checkpoint " + d + "/c.ckpt --json " + d + "/c.json");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string straight = read_text(d + "/a.ckpt"), resumed = read_text(d + "/c.ckpt");
  EXPECT_EQ(value_of(straight, "tick"), "300");
  ASSERT_FALSE(value_of(straight, "state_hash").empty());
  EXPECT_EQ(value_of(resumed, "state_hash"), value_of(straight, "state_hash")) << "bit-identical state";
  for (const char* k : {"cycles", "commands", "peak_speed", "peak_kinetic", "peak_displacement", "cycle_drift", "cycle_end_kinetic", "checks"})
    EXPECT_EQ(value_of(resumed, k), value_of(straight, k)) << k;
  const std::string ja = read_text(d + "/a.json"), jc = read_text(d + "/c.json");
  EXPECT_NE(jc.find("\"cycles\": 3"), std::string::npos) << jc;
  auto figures = [](const std::string& j) {  // the measured figures after cpu_s (time spent differs)
    const size_t b = j.find("\"cycle_drift_max_mm\"");
    return b == std::string::npos ? std::string() : j.substr(b, j.find('}', b) - b);
  };
  ASSERT_FALSE(figures(ja).empty()) << ja;
  EXPECT_EQ(figures(jc), figures(ja));
}

TEST(CliStress, ACheckpointOfAnotherScriptOrAlreadyLongEnoughOrDamagedIsBadInput) {
  const auto d = cli_temp_dir("stress_soak_resume_bad").string();
  const std::string script = loop_script(d);
  const std::string scene = std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml";
  const std::string base = "stress " + scene + " --cases soak";
  ASSERT_EQ(run_cli(base + " --script " + script + " --soak 0.05 --checkpoint " + d + "/b.ckpt").code, 0);
  auto r = run_cli(base + " --script none --soak 0.1 --resume " + d + "/b.ckpt");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("b.ckpt:2: 'script'"), std::string::npos) << r.out;
  r = run_cli(base + " --script " + script + " --soak 0.05 --resume " + d + "/b.ckpt");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("longer --soak"), std::string::npos) << r.out;
  std::string text = read_text(d + "/b.ckpt");
  write(d, "cut.ckpt", text.substr(0, text.size() - 100));
  r = run_cli(base + " --script " + script + " --soak 0.1 --resume " + d + "/cut.ckpt");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("cut.ckpt:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("'state'"), std::string::npos) << r.out;
  r = run_cli("stress " + scene + " --soak 0.1 --checkpoint " + d + "/x.ckpt");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--cases soak"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(d + "/x.ckpt"));
}

TEST(CliStress, UnknownCaseAndAForeignScriptAreBadInput) {
  const auto d = cli_temp_dir("stress_soak_bad").string();
  const std::string scene = std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml";
  auto r = run_cli("stress " + scene + " --cases soak,nonsense");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("nonsense"), std::string::npos) << r.out;
  const std::string other = write(d, "other.yaml", "scenario: biopsy\nduration_s: 1\ntimeline:\n  - {t: 0.0, probe: {insertion_mm: 45}}\n");
  r = run_cli("stress " + scene + " --cases soak --script " + other);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("biopsy"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ps::test
