// `prostatesim simulate` and `prostatesim validate` with the probe and filling, as a user runs
// them: the per-particle displacement files, the prostate's displacement printed, and the
// issue's bad input (probe outside the rectum or in bone, target volume <= 0, too fast a fill)
// giving exit 2 naming file:line and field, or a clamped and reported value.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/app/run_cli.h"

namespace {

namespace fs = std::filesystem;
const std::string kSource = PROSTATESIM_SOURCE_DIR;

fs::path temp_dir(const std::string& name) { return ps::test::cli_temp_dir("probe_" + name); }
std::string read(const fs::path& p) { return ps::test::read_text(p); }
int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// The probe test scene with one substring replaced, written to dir/name.
fs::path scene_with(const fs::path& dir, const std::string& name, const std::string& from, const std::string& to) {
  std::string y = read(kSource + "/config/validation/probe_pelvis_box.yaml");
  const size_t at = y.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) y.replace(at, from.size(), to);
  std::ofstream(dir / name) << y;
  return dir / name;
}
int line_of(const fs::path& file, const std::string& text) {
  const std::string y = read(file);
  return lines(y.substr(0, y.find(text))) + 1;
}

TEST(CliProbe, ValidateWritesTheDisplacementFileAndPrintsTheProstateRows) {
  const fs::path dir = temp_dir("val");
  const auto r = ps::test::run_cli("validate probe_tilt --root " + kSource + " --out " + (dir / "files").string() +
                                   " --json " + (dir / "rows.json").string());
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* row : {"prostate displacement mean", "prostate displacement max", "prostate base mean",
                          "prostate apex mean", "probe penetration"})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
  const std::string csv = read(dir / "files" / "probe_tilt_displacement.csv");
  ASSERT_FALSE(csv.empty()) << r.out;
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "id,component,zone,x0_mm,y0_mm,z0_mm,x_mm,y_mm,z_mm,ux_mm,uy_mm,uz_mm,u_mm");
  EXPECT_EQ(lines(csv), 1 + 695);  // header + every particle of the scene
  EXPECT_NE(csv.find(",prostate,base,"), std::string::npos);
  const auto rows = nlohmann::json::parse(read(dir / "rows.json"));  // --json unchanged
  for (const auto& row : rows) EXPECT_EQ(row.size(), 5u);
}

TEST(CliProbe, SimulateWritesDisplacementAndPrintsTheProstateMotion) {
  const fs::path dir = temp_dir("sim");
  const auto r = ps::test::run_cli("simulate " + kSource + "/config/validation/probe_pelvis_box.yaml --duration 0.05 --out " +
                                   (dir / "run").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("prostate displacement: mean"), std::string::npos) << r.out;
  const std::string csv = read(dir / "run" / "displacement.csv");
  EXPECT_EQ(csv.substr(0, csv.find(',')), "id");
  EXPECT_EQ(lines(csv), 1 + 695);
}

TEST(CliProbe, ProbeOutsideTheRectumOrInBoneExits2NamingThePoseAndWritesNothing) {
  const fs::path dir = temp_dir("bad_probe");
  // outside the rectum: entry moved 30 mm anterior, into the prostate
  const fs::path out_of = scene_with(dir, "outside.yaml", "entry_mm: [0, 0, -28]", "entry_mm: [0, 30, -28]");
  auto r = ps::test::run_cli("simulate " + out_of.string() + " --out " + (dir / "o1").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("outside.yaml:" + std::to_string(line_of(out_of, "pose: {insertion_mm"))), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("probe.pose"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("outside the rectum"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "o1"));
  // in bone: a rigid block around the probe's tip
  const fs::path bone = scene_with(dir, "bone.yaml", "links:",
                                   "  - {name: pubis, type: rigid, material: fat, spacing_mm: 4, box: {min_mm: [-4, -4, 14], max_mm: [4, 4, 20]}}\nlinks:");
  r = ps::test::run_cli("simulate " + bone.string() + " --out " + (dir / "o2").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("probe.pose"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bone"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "o2"));
}

TEST(CliProbe, TargetVolumeNotPositiveExits2AndTooFastAFillIsClampedAndReported) {
  const fs::path dir = temp_dir("bad_fill");
  const fs::path zero = scene_with(dir, "zero.yaml", "target_factor: 2", "target_ml: 0");
  auto r = ps::test::run_cli("simulate " + zero.string() + " --out " + (dir / "o1").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("zero.yaml:" + std::to_string(line_of(zero, "target_ml: 0"))), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("filling.schedule[0].target_ml"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "o1"));
  // the scene's own limit is 1000 ml/s; 5000 ml/s is clamped to it and the run goes on
  const fs::path fast = scene_with(dir, "fast.yaml", "target_factor: 2, ramp_s: [0.02, 0.12]", "rate_ml_s: 5000, ramp_s: [0.0, 0.01]");
  r = ps::test::run_cli("simulate " + fast.string() + " --duration 0.03 --out " + (dir / "o2").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("filling: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fast.yaml:" + std::to_string(line_of(fast, "rate_ml_s: 5000")) + ": filling.schedule[0]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("clamped to 1000 ml/s"), std::string::npos) << r.out;
}

}  // namespace
