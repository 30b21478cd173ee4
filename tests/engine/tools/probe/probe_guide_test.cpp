// Needles carried by the probe: a biopsy needle held in the probe's guide follows the guide as
// the probe tilts (commanded tip exactly on the guide line, direction at the clinical angle to the
// probe axis, the tip dragged onto it once the probe stops), and a brachytherapy needle in a
// template hole runs parallel to the probe and stays put when the probe is stepped in.
#include "engine/tools/probe/probe_guide.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "engine/mesh/mesh_import.h"
#include "engine/mesh/mesh_query.h"
#include "engine/realtime/script.h"
#include "engine/tools/probe/probe_geometry.h"
#include "engine/util/error.h"
#include "tests/engine/tools/probe/probe_scene.h"

namespace ps {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string mm3(const Vec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "[%.6f, %.6f, %.6f]", v.x() * 1e3, v.y() * 1e3, v.z() * 1e3);
  return b;
}

// The probe scene with one 18G needle starting on `path`.
test::ProbeScene scene_with_needle(const NeedlePath& path) {
  const std::string y = test::probe_scene_yaml() + "needles:\n  instruments:\n    - {name: n1, preset: biopsy_18g, start_mm: " +
                        mm3(path.entry) + ", direction: " + mm3(path.direction * 1e3) + "}\n";
  return test::build_probe_scene(parse_scenario_text(y, "guide.yaml"), false);
}

NeedlePath rest_path(bool guide, int col = 0, int row = 0) {
  const ScenarioSpec spec = parse_scenario_file(test::probe_scene_path());
  auto m = compile_scenario(spec);
  ProbeTool probe(*spec.probe, *m);
  return guide ? probe.biopsy_guide() : probe.template_hole(col, row);
}

TEST(ProbeGuide, BiopsyNeedleFollowsTheGuideAsTheProbeTilts) {
  test::ProbeScene s = scene_with_needle(rest_path(true));
  ASSERT_NE(s.needles, nullptr);
  ProbePose target = s.probe->pose();
  target.tilt = 5 * kDeg;
  s.probe->move_to(target, 0.0);  // at the scene's speed limit: ~42 ms
  const double depth = 0.002;     // 2 mm out of the guide: still in the rectal lumen
  for (int k = 0; k < 80; ++k) {
    hold_needle_in_biopsy_guide(*s.needles, 0, *s.probe, depth);
    const NeedlePath g = s.probe->biopsy_guide();
    ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.m);
    const NeedleReadout& r = s.needles->readout(0);
    // commanded exactly on the guide (as it was at the start of the tick) at the clinical angle
    ASSERT_NEAR((r.command_tip - (g.entry + depth * g.direction)).norm(), 0.0, 1e-15) << "tick " << k;
    ASSERT_NEAR((r.direction - g.direction).norm(), 0.0, 1e-15);
  }
  const NeedlePath g = s.probe->biopsy_guide();
  EXPECT_NEAR(std::acos(g.direction.dot(s.probe->frame().axis())) / kDeg, 20.0, 1e-9);
  EXPECT_NEAR(s.probe->pose().tilt, 5 * kDeg, 1e-15);
  // the guide moved with the probe and the tip followed it
  const NeedlePath g0 = rest_path(true);
  EXPECT_GT((g.entry - g0.entry).norm(), 1e-3);
  const NeedleReadout& r = s.needles->readout(0);
  const double lag = (r.tip - (g.entry + depth * g.direction)).norm();
  std::printf("guide exit moved %.2f mm; tip %.3f mm from the guide point, tissue force on the needle %.3f N\n",
              (g.entry - g0.entry).norm() * 1e3, lag * 1e3, r.tissue_force.norm());
  // the tip follows the guide; what lag remains is the coupling spring (2 N/mm) holding the
  // tissue's pull on the needle (the tilted guide brings the tip against the rectal wall)
  EXPECT_LT(lag, 0.25 * (g.entry - g0.entry).norm());
  EXPECT_LT(lag, r.tissue_force.norm() / s.needles->spec(0).coupling_stiffness + 1e-4);
}

TEST(ProbeGuide, TemplateNeedleRunsParallelToTheProbeAndIgnoresTheStepper) {
  test::ProbeScene s = scene_with_needle(rest_path(false, 6, 0));
  const NeedlePath h0 = s.probe->template_hole(6, 0);
  ProbePose target = s.probe->pose();
  target.insertion += 0.005;  // the stepper moves the probe 5 mm through the template
  s.probe->move_to(target, 0.0);
  for (int k = 0; k < 60; ++k) {
    hold_needle_in_template_hole(*s.needles, 0, *s.probe, 6, 0, 0.0);
    ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.m);
  }
  const NeedleReadout& r = s.needles->readout(0);
  EXPECT_NEAR((r.direction - s.probe->frame().axis()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((r.command_tip - h0.entry).norm(), 0.0, 1e-15);  // the template did not move
  EXPECT_NEAR(s.probe->pose().insertion, target.insertion, 1e-15);
  EXPECT_THROW(hold_needle_in_template_hole(*s.needles, 0, *s.probe, 13, 0, 0.0), InputError);
}

}  // namespace
}  // namespace ps

namespace ps {
namespace {

// The default biopsy scene (config/biopsy.yaml with config/scripts/biopsy.yaml): its needle rides
// in the probe's guide; at the script's probe pose the guide's line
// leaves the rectal lumen through the wall into the gland (rest geometry, assets/anatomy): the
// shipped script's core (fired from its prefire depth) lies in the gland and the tip stops inside.
TEST(ProbeGuide, DefaultBiopsyGuideCrossesTheRectalWallIntoTheGland) {
  const std::string dir = std::string(PROSTATESIM_SOURCE_DIR) + "/";
  const ScenarioSpec spec = parse_scenario_file(dir + "config/biopsy.yaml");
  const Script script = parse_script_file(dir + "config/scripts/biopsy.yaml");
  ProbePose pose = spec.probe->pose;
  double prefire = 0.0;
  for (const ScriptEntry& e : script.entries) {
    if (e.action == "probe" && e.has_insertion) pose.insertion = e.insertion;
    if (e.action == "fire") break;
    if (e.action == "needle") prefire = e.depth;
  }
  const NeedlePath g = biopsy_guide_path(*spec.probe, probe_frame(*spec.probe, rectal_frame(*spec.probe), pose));
  const NeedleSpec& n = spec.needles.needles.at(0);
  // the needle rides in the guide (guide: biopsy): it starts at the guide's exit at the probe's start pose
  const NeedlePath g0 = biopsy_guide_path(*spec.probe, probe_frame(*spec.probe, rectal_frame(*spec.probe), spec.probe->pose));
  EXPECT_LT((n.start - g0.entry).norm(), 0.05e-3) << "the needle starts at the guide's exit";
  EXPECT_LT((n.direction - g0.direction).norm(), 1e-4) << "and runs along the guide";
  MeshImportOptions mm;
  mm.units = "mm";
  const MeshQuery prostate(import_mesh(dir + "assets/anatomy/prostate.obj", mm));
  const MeshQuery rectum(import_mesh(dir + "assets/anatomy/rectum.obj", mm));
  // first points along the guide (0.1 mm steps) outside the rectum and inside the gland
  double wall = -1, gland = -1;
  for (double s = 0; s < 0.08 && gland < 0; s += 1e-4) {
    const Vec3 q = g.entry + s * g.direction;
    if (wall < 0 && !rectum.inside(q)) wall = s;
    if (gland < 0 && prostate.inside(q)) gland = s;
  }
  const BiopsyGunSpec gun = *n.gun;
  const double tip = prefire + gun.stroke;
  const double lo = tip - gun.notch_offset - gun.notch_length, hi = tip - gun.notch_offset;
  int in = 0, all = 0;
  for (double s = lo; s <= hi; s += 1e-4, ++all) in += prostate.inside(g.entry + s * g.direction);
  std::printf("guide: rectal wall %.1f mm, capsule %.1f mm; prefire %.1f mm, tip after the stroke %.1f mm, notch %.0f %% in "
              "the gland\n", wall * 1e3, gland * 1e3, prefire * 1e3, tip * 1e3, 100.0 * in / all);
  ASSERT_GT(wall, 0.0) << "the needle leaves the rectal lumen";
  ASSERT_GT(gland, wall) << "then enters the gland, posteriorly (peripheral zone)";
  EXPECT_LE(prefire, wall + 1e-3) << "the gun is fired from the rectal wall: the stroke punctures it";
  EXPECT_TRUE(prostate.inside(g.entry + tip * g.direction)) << "the tip stops inside the gland";
  EXPECT_GT(in, all / 2) << "most of the notch lies in the gland";
}

}  // namespace
}  // namespace ps
