// instruments.csv (replay --out): a script that rolls the probe 30 deg and then advances the
// needle in the guide shows the needle's path turned 30 deg about the probe's axis, row by row,
// with the probe's pose and force beside it.
#include "engine/io/instruments_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/script.h"
#include "engine/tools/probe/probe.h"

namespace ps {
namespace {

std::vector<std::vector<std::string>> rows_of(const std::string& text) {
  std::vector<std::vector<std::string>> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream l(line);
    std::string c;
    while (std::getline(l, c, ',')) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    out.push_back(cells);
  }
  return out;
}

TEST(InstrumentsCsv, ARolledProbeTurnsTheNeedlesPathAboutItsAxis) {
  Scene sc = load_scene(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
  const Script s = parse_script_text(
      "scenario: biopsy\ntimeline:\n"
      "  - {t: 0.0, probe: {insertion_mm: 45, roll_deg: 30}, over_s: 0.5}\n"
      "  - {t: 0.6, needle: biopsy_1, depth_mm: 0}\n"
      "  - {t: 1.0, needle: biopsy_1, depth_mm: 10}\n",
      "roll30.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  InstrumentsCsv csv;
  csv.add(sc);
  for (int k = 1; k <= 10; ++k) {
    ASSERT_TRUE(run.advance_to(k * 50));  // a row every 0.1 s
    csv.add(sc);
  }
  const std::string text = std::string(InstrumentsCsv::header()) + csv.text();
  const auto rows = rows_of(text);
  ASSERT_EQ(rows.size(), 12u);
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "t_s,needle,tip_x_mm,tip_y_mm,tip_z_mm,dir_x,dir_y,dir_z,depth_mm,probe_x_mm,probe_y_mm,probe_z_mm,"
            "probe_roll_deg,probe_tilt_deg,probe_yaw_deg,probe_insertion_mm,probe_force_n");
  for (size_t r = 1; r < rows.size(); ++r) ASSERT_EQ(rows[r].size(), 17u) << r;
  auto dir = [&](size_t r) { return Vec3(std::stod(rows[r][5]), std::stod(rows[r][6]), std::stod(rows[r][7])); };
  const auto& probe = *sc.tools.as<ProbeTool>();
  const Vec3 axis = probe.frame().axis();  // a roll leaves the axis where it was
  const Vec3 a = dir(1), b = dir(rows.size() - 1);
  EXPECT_NEAR(a.norm(), 1.0, 1e-5);
  EXPECT_NEAR(b.norm(), 1.0, 1e-5);
  const Vec3 pa = a - a.dot(axis) * axis, pb = b - b.dot(axis) * axis;
  const double turn = std::atan2(axis.dot(pa.cross(pb)), pa.dot(pb)) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(std::abs(turn), 30.0, 0.01);
  EXPECT_NEAR(std::stod(rows.back()[12]), 30.0, 1e-3);   // probe_roll_deg
  EXPECT_NEAR(std::stod(rows.back()[15]), 45.0, 1e-3);   // probe_insertion_mm
  EXPECT_NEAR(std::stod(rows.back()[8]), 10.0, 1.0);     // depth along the guide: 10 mm, the coupling's lag aside
  EXPECT_EQ(rows.back()[1], "biopsy_1");
}

}  // namespace
}  // namespace ps
