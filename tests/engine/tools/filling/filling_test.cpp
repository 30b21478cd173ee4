// Organ filling: the target volume follows the schedule and live commands exactly, the volume
// projection holds the organ at it to round-off, limits are clamped and reported or refused, and
// doubling the bladder of the primitive pelvis scene pushes the prostate base away (paper §5.3).
#include "engine/tools/filling/filling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/stages.h"
#include "engine/tools/probe/displacement_field.h"
#include "engine/util/error.h"
#include "engine/util/state_io.h"

namespace ps {
namespace {

constexpr double kMl = 1e-6;

// A 40 mm membrane cube (64 ml) on a fixed base, incompressible, plus a compressible lump.
std::string cube_with(const std::string& filling) {
  return "name: fill\ngravity_m_s2: [0, 0, 0]\n"
         "materials: {wall: {young_kpa: 10, damping_1_s: 100, incompressible: true}, soft: {young_kpa: 10}}\n"
         "components:\n"
         "  - {name: bladder, material: wall, spacing_mm: 10, fill: surface, box: {min_mm: [0, 0, 0], max_mm: [40, 40, 40]}}\n"
         "  - {name: lump, material: soft, spacing_mm: 10, box: {min_mm: [60, 0, 0], max_mm: [80, 20, 20]}}\n"
         "constraints:\n  - fix: {component: bladder, region: {box: {min_mm: [-1, -1, -1], max_mm: [99, 99, 0.5]}}}\n" +
         filling;
}

struct FillRun {
  ScenarioSpec spec;
  std::shared_ptr<const Model> m;
  std::unique_ptr<Simulation> sim;
  FillingTool* tool = nullptr;
  int surface = -1;
  double rest = 0.0;                 // [m^3]
  double worst_hold = 0.0;           // max |V / V_target - 1| after any tick
};

FillRun start(const std::string& yaml) {
  FillRun r;
  r.spec = parse_scenario_text(yaml, "fill.yaml");
  r.m = compile_scenario(r.spec);
  r.sim = std::make_unique<Simulation>(r.m);
  auto t = make_filling_tool(r.spec, *r.m);
  r.tool = t.get();
  r.sim->add_tool(std::move(t));
  r.surface = r.m->components[r.m->find_component("bladder")].surface;
  r.rest = r.m->surfaces[r.surface].rest_volume;
  return r;
}

void ticks(FillRun& r, int n) {
  for (int i = 0; i < n; ++i) {
    ASSERT_TRUE(r.sim->tick()) << r.sim->state().fault.describe(*r.m);
    const State& s = r.sim->state();
    r.worst_hold = std::max(r.worst_hold, std::abs(surface_volume(r.m->surfaces[r.surface], s.x) / s.target_volume[r.surface] - 1.0));
  }
}

TEST(Filling, RateIsFollowedAndTheVolumeHeldToRoundOff) {
  FillRun r = start(cube_with("filling:\n  schedule: [{component: bladder, rate_ml_s: 4, ramp_s: [0.05, 0.25]}]\n"));
  EXPECT_NEAR(r.rest, 64 * kMl, 1e-12);
  ticks(r, 50);
  EXPECT_DOUBLE_EQ(r.sim->state().target_volume[r.surface], r.rest);
  ticks(r, 100);  // t = 0.15
  EXPECT_NEAR(r.tool->target_volume("bladder"), r.rest + 4 * kMl * 0.1, 1e-15);
  ticks(r, 150);  // t = 0.30: held at the end value
  EXPECT_NEAR(r.sim->state().target_volume[r.surface], r.rest + 0.8 * kMl, 1e-15);
  EXPECT_LT(r.worst_hold, 1e-9);
  EXPECT_TRUE(r.tool->reports().empty());
}

TEST(Filling, TargetOrFactorIsReachedLinearlyAndALaterSegmentTakesOver) {
  FillRun r = start(cube_with(
      "filling:\n  max_rate_ml_s: 200\n  schedule:\n"
      "    - {component: bladder, target_factor: 1.5, ramp_s: [0, 0.2]}\n"
      "    - {component: bladder, target_ml: 70, ramp_s: [0.1, 0.2]}\n"));
  ticks(r, 50);
  EXPECT_NEAR(r.tool->target_volume("bladder"), r.rest * (1 + 0.5 * 0.25), 1e-15);
  ticks(r, 50);  // t = 0.1: the second segment starts from 80 ml and goes to 70 ml
  EXPECT_NEAR(r.tool->target_volume("bladder"), 80 * kMl, 1e-15);
  ticks(r, 50);
  EXPECT_NEAR(r.tool->target_volume("bladder"), 75 * kMl, 1e-15);
  ticks(r, 60);
  EXPECT_NEAR(r.tool->target_volume("bladder"), 70 * kMl, 1e-15);
  EXPECT_LT(r.worst_hold, 1e-9);
}

TEST(Filling, RatesBeyondThePhysiologicalLimitAreClampedAndReported) {
  FillRun r = start(cube_with(
      "filling:\n  schedule:\n"
      "    - {component: bladder, rate_ml_s: 8, ramp_s: [0, 0.1]}\n"
      "    - {component: bladder, target_ml: 60, ramp_s: [0.1, 0.2]}\n"));
  ASSERT_EQ(r.tool->reports().size(), 2u);
  EXPECT_NE(r.tool->reports()[0].find("fill.yaml:"), std::string::npos) << r.tool->reports()[0];
  EXPECT_NE(r.tool->reports()[0].find("clamped to 5 ml/s"), std::string::npos) << r.tool->reports()[0];
  EXPECT_NE(r.tool->reports()[1].find("lengthened"), std::string::npos) << r.tool->reports()[1];
  ticks(r, 100);
  EXPECT_NEAR(r.tool->target_volume("bladder"), r.rest + 0.5 * kMl, 1e-15);  // 5 ml/s, not 8
  // 64.5 -> 60 ml at 5 ml/s takes 0.9 s, not 0.1 s: at t = 0.2 it is 0.5 ml lower
  ticks(r, 100);
  EXPECT_NEAR(r.tool->target_volume("bladder"), 64.0 * kMl, 1e-15);
  EXPECT_LT(r.worst_hold, 1e-9);
}

// A session sends many live commands: the segments that have ended are dropped (compact()), so the
// schedule never outgrows the slots reserved at construction (no allocation on the physics
// thread), the saved state keeps its length, the target still follows every command exactly, and
// a save taken mid-way restores to the same targets.
TEST(Filling, ThousandsOfLiveCommandsKeepTheSavedLengthAndFollowTheirTargets) {
  const std::string y = cube_with("filling:\n  schedule: [{component: bladder, rate_ml_s: 1, ramp_s: [0, 0.5]}]\n");
  const ScenarioSpec spec = parse_scenario_text(y, "fill.yaml");
  auto m = compile_scenario(spec);
  FillingTool tool(*spec.filling, *m);
  State s = make_state(*m);
  const int si = m->components[0].surface;
  const double v0 = m->surfaces[si].rest_volume;
  auto at = [&](FillingTool& t, double time) {
    s.time = time - 1e-3;
    t.boundary_conditions(*m, s, 1e-3);
    return s.target_volume[si];
  };
  auto saved = [](FillingTool& t) {
    std::vector<uint8_t> b;
    StateIO io(b, StateIO::Save);
    t.serialize(io);
    io.finish();
    return b;
  };
  const size_t length = saved(tool).size();
  // the scripted 1 ml/s runs to 0.5 s (+0.5 ml); from 1 s, +2 ml/s and -2 ml/s for 10 ms each
  EXPECT_NEAR(at(tool, 1.0), v0 + 0.5 * kMl, 1e-15);
  std::vector<uint8_t> mid;
  for (int k = 0; k < 3000; ++k) {
    tool.set_rate("bladder", (k % 2 ? -2.0 : 2.0) * kMl);
    const double t = 1.0 + 0.01 * (k + 1);
    ASSERT_NEAR(at(tool, t), v0 + 0.5 * kMl + (k % 2 ? 0.0 : 0.02 * kMl), 1e-14) << "command " << k;
    ASSERT_EQ(saved(tool).size(), length) << "command " << k;
    if (k == 1499) mid = saved(tool);
  }
  // every open-ended rate is reported where the volume range would stop it: the ring keeps the
  // latest ones and counts the rest
  EXPECT_EQ(tool.report_ring().total(), 3000);
  EXPECT_EQ(tool.report_ring().size(), ToolReportRing::kCapacity);
  EXPECT_EQ(tool.reports().front(), std::to_string(3000 - ToolReportRing::kCapacity) +
                                        " earlier filling reports were dropped (ring of " + std::to_string(ToolReportRing::kCapacity) + ")");
  EXPECT_EQ(tool.report_ring().at(0).code, ToolReportCode::FillStops);
  // restored mid-way, the same commands give the same targets to the bit
  FillingTool again(*spec.filling, *m);
  StateIO in(mid, StateIO::Restore);
  again.serialize(in);
  double a = 0.0, b = 0.0;
  for (int k = 1500; k < 1600; ++k) {
    again.set_rate("bladder", (k % 2 ? -2.0 : 2.0) * kMl);
    a = at(again, 1.0 + 0.01 * (k + 1) + 0.005);
  }
  FillingTool ref(*spec.filling, *m);
  at(ref, 1.0);
  for (int k = 0; k < 1600; ++k) {
    ref.set_rate("bladder", (k % 2 ? -2.0 : 2.0) * kMl);
    b = at(ref, 1.0 + 0.01 * (k + 1) + (k >= 1500 ? 0.005 : 0.0));
  }
  EXPECT_EQ(a, b);
  EXPECT_NEAR(a, v0 + 0.51 * kMl, 1e-14);  // 10 ms of +2 ml/s then 5 ms of -2 ml/s on 64.5 ml
}

TEST(Filling, LiveCommandsTakeOverAndAreClampedToRateAndVolumeLimits) {
  const std::string y = cube_with("filling:\n  schedule: [{component: bladder, rate_ml_s: 1, ramp_s: [0, 10]}]\n");
  const ScenarioSpec spec = parse_scenario_text(y, "fill.yaml");
  auto m = compile_scenario(spec);
  FillingTool tool(*spec.filling, *m);
  State s = make_state(*m);
  const int si = m->components[0].surface;
  const double v0 = m->surfaces[si].rest_volume;
  auto at = [&](double t) {
    s.time = t - 1e-3;
    tool.boundary_conditions(*m, s, 1e-3);
    return s.target_volume[si];
  };
  EXPECT_NEAR(at(1.0), v0 + 1 * kMl, 1e-15);
  EXPECT_DOUBLE_EQ(tool.set_rate("bladder", 20 * kMl), 5 * kMl);  // clamped
  EXPECT_NEAR(at(2.0), v0 + 6 * kMl, 1e-14);
  const double used = tool.fill_to("bladder", 50 * kMl, 1.0);      // 20 ml in 1 s: too fast
  EXPECT_NEAR(used, 20.0 / 5.0, 1e-12);
  EXPECT_NEAR(at(4.0), 60 * kMl, 1e-14);
  EXPECT_NEAR(at(7.0), 50 * kMl, 1e-14);
  // draining without end stops at 10% of the rest volume
  tool.set_rate("bladder", -5 * kMl);
  EXPECT_NEAR(at(100.0), 0.1 * v0, 1e-14);
  // a target beyond 10x the rest volume is clamped there
  tool.fill_to("bladder", 1e-3, 1e6);
  EXPECT_NEAR(at(2e6), 10 * v0, 1e-13);
  EXPECT_GE(tool.reports().size(), 4u);
  for (const auto& line : tool.reports()) EXPECT_NE(line.find("live filling command"), std::string::npos) << line;
  EXPECT_THROW(tool.fill_to("bladder", 0.0, 1.0), InputError);
  EXPECT_THROW(tool.fill_to("bladder", -1 * kMl, 1.0), InputError);
  EXPECT_THROW(tool.fill_to("bladder", 70 * kMl, -1.0), InputError);
  EXPECT_THROW(tool.set_rate("lump", 1 * kMl), InputError);
  EXPECT_THROW(tool.set_rate("bladder", std::nan("")), InputError);
}

InputError fill_error(const std::string& filling) {
  try {
    const ScenarioSpec spec = parse_scenario_text(cube_with(filling), "bad.yaml");
    auto m = compile_scenario(spec);
    FillingTool tool(*spec.filling, *m);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for " << filling;
  return InputError("", 0, "", "");
}

TEST(Filling, BadScheduleIsAnInputErrorNamingTheEntry) {
  auto field = [](const std::string& f) { return fill_error("filling:\n  schedule:\n" + f).field(); };
  EXPECT_EQ(field("    - {component: bladder, target_ml: 0, ramp_s: [0, 1]}\n"), "filling.schedule[0].target_ml");
  EXPECT_EQ(field("    - {component: bladder, target_ml: -20, ramp_s: [0, 1]}\n"), "filling.schedule[0].target_ml");
  EXPECT_EQ(field("    - {component: bladder, target_factor: 0, ramp_s: [0, 1]}\n"), "filling.schedule[0].target_factor");
  EXPECT_EQ(field("    - {component: lump, rate_ml_s: 1, ramp_s: [0, 1]}\n"), "filling.schedule[0].component");
  EXPECT_EQ(field("    - {component: kidney, rate_ml_s: 1, ramp_s: [0, 1]}\n"), "filling.schedule[0].component");
  EXPECT_EQ(field("    - {component: bladder, rate_ml_s: 1, target_ml: 3, ramp_s: [0, 1]}\n"), "filling.schedule[0]");
  EXPECT_EQ(field("    - {component: bladder, rate_ml_s: 1}\n"), "filling.schedule[0].ramp_s");
  EXPECT_EQ(field("    - {component: bladder, rate_ml_s: 1, ramp_s: [0, 1]}\n    - {component: bladder, target_ml: 900, ramp_s: [1, 500]}\n"),
            "filling.schedule[1]");
  EXPECT_EQ(field("    - {component: bladder, rate_ml_s: -5, ramp_s: [0, 20]}\n"), "filling.schedule[0].rate_ml_s");
  EXPECT_EQ(fill_error("filling: {max_rate_ml_s: 0, schedule: [{component: bladder, rate_ml_s: 1, ramp_s: [0, 1]}]}\n").field(),
            "filling.max_rate_ml_s");
  const InputError e = fill_error("filling:\n  schedule:\n    - {component: bladder, target_ml: 0, ramp_s: [0, 1]}\n");
  EXPECT_EQ(e.line(), 11);
  EXPECT_NE(std::string(e.what()).find("> 0"), std::string::npos) << e.what();
}

// ---- the paper's bladder-doubling experiment (§5.3, Fig. 11-12) in the primitive scene --------

TEST(Filling, DoublingTheBladderMovesTheProstateBaseDownAndBackWithBothVolumesExact) {
  const ScenarioSpec spec = parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml");
  auto m = compile_scenario(spec);
  Simulation sim(m);
  auto t = make_filling_tool(spec, *m);  // bladder x2 over [0.02, 0.12] s; no probe here
  FillingTool* tool = t.get();
  sim.add_tool(std::move(t));
  const int pc = m->find_component("prostate"), bc = m->find_component("bladder");
  const Surface& bs = m->surfaces[m->components[bc].surface];
  const Surface& ps_ = m->surfaces[m->components[pc].surface];
  const std::vector<Vec3> ref = sim.state().x;
  double worst = 0.0;
  for (int i = 0; i < 180; ++i) {
    ASSERT_TRUE(sim.tick()) << sim.state().fault.describe(*m);
    worst = std::max(worst, std::abs(surface_volume(bs, sim.state().x) / tool->target_volume("bladder") - 1.0));
    worst = std::max(worst, std::abs(surface_volume(ps_, sim.state().x) / ps_.rest_volume - 1.0));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(surface_volume(bs, sim.state().x), 2.0 * bs.rest_volume, 1e-9 * bs.rest_volume);
  const DisplacementStats d = displacement_stats(*m, pc, ref, sim.state().x, Vec3::UnitZ());
  std::printf("bladder %.1f -> %.1f ml: prostate mean %.3f mm, max %.3f mm; inferior motion base %.3f, mid %.3f, apex %.3f mm\n",
              bs.rest_volume / kMl, 2 * bs.rest_volume / kMl, d.all.mean * 1e3, d.all.max * 1e3, -d.base.mean_vec.z() * 1e3,
              -d.mid.mean_vec.z() * 1e3, -d.apex.mean_vec.z() * 1e3);
  // the base (next to the bladder) is pushed down (inferiorly, away from the bladder) and back
  // (posteriorly, toward the rectum), down more than the apex
  EXPECT_LT(d.base.mean_vec.z(), -0.3e-3);
  EXPECT_LT(d.base.mean_vec.y(), -0.1e-3);
  std::printf("prostate base motion: %.3f mm down, %.3f mm back\n", -d.base.mean_vec.z() * 1e3, -d.base.mean_vec.y() * 1e3);
  EXPECT_GT(-d.base.mean_vec.z(), 1.5 * std::abs(d.apex.mean_vec.z()));
  EXPECT_GT(d.base.mean, d.apex.mean);
  EXPECT_LT(d.all.max, 0.02);  // no blow-up: well under the prostate's size
  // the per-particle file a viewer colours: one row per prostate particle
  const std::string path = (std::filesystem::temp_directory_path() / "ps_bladder_doubling_displacement.csv").string();
  write_displacement_csv(path, *m, pc, ref, sim.state().x, Vec3::UnitZ());
  std::ifstream in(path);
  std::string line;
  int rows = -1;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, m->components[pc].particle_count);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ps
