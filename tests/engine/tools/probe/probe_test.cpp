// Endorectal probe in the primitive pelvis scene (config/validation/probe_pelvis_box.yaml):
// pushing and tilting move the prostate, nothing ever sits inside the probe by more than 0.1 mm
// (checked independently of the tool's own read-out), the paper's imposed mode, commands and
// speed limits, reaction force, determinism and bad input.
#include "engine/tools/probe/probe.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/stages.h"
#include "engine/tools/probe/displacement_field.h"
#include "engine/tools/filling/filling.h"
#include "engine/util/error.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/tools/probe/probe_scene.h"

namespace ps {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

using Scene = test::ProbeScene;

// The test scene; `edit` may change the spec before compiling; filling only when asked.
template <class Edit>
Scene make_scene(Edit edit, bool with_filling = false) {
  ScenarioSpec spec = parse_scenario_file(test::probe_scene_path());
  edit(spec);
  return test::build_probe_scene(spec, with_filling);
}
Scene make_scene(bool with_filling = false) { return test::build_probe_scene(with_filling); }

// Deepest penetration of a movable (not fixed, not rigid) particle into the probe, computed
// from the state and the probe's frame, not from the tool's read-out [m].
double penetration(const Scene& s) {
  const Model& m = *s.m;
  double worst = 0.0;
  for (int p = 0; p < m.particle_count(); ++p) {
    if (m.inv_mass[p] == 0.0 || m.locked_axes[p] != 0) continue;
    worst = std::max(worst, -capsule_signed_distance(s.probe->frame().capsule, s.sim->state().x[p]));
  }
  return worst;
}

void run(Scene& s, int ticks) {
  for (int i = 0; i < ticks; ++i) {
    ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.m);
    s.worst_penetration = std::max(s.worst_penetration, penetration(s));
  }
}

DisplacementStats prostate_motion(const Scene& s, const std::vector<Vec3>& ref) {
  return displacement_stats(*s.m, s.m->find_component("prostate"), ref, s.sim->state().x, Vec3::UnitZ());
}

ProbePose pushed(const ProbeTool& p, double offset_y, double tilt = 0.0) {
  ProbePose t = p.pose();
  t.offset = Vec3(0, offset_y, 0);
  t.tilt = tilt;
  return t;
}

// ---- geometry -------------------------------------------------------------------------------

TEST(ProbeGeometry, PoseMovesTheCapsuleAsDocumented) {
  ProbeSpec spec;
  spec.entry = Vec3(0, 0, -0.03);
  spec.length = 0.05;
  spec.radius = 0.01;
  const RectalFrame rf = rectal_frame(spec);
  EXPECT_NEAR((rf.lateral - Vec3(-1, 0, 0)).norm(), 0.0, 1e-15);  // a x n = z x y = -x
  ProbePose pose;
  pose.insertion = 0.06;
  ProbeFrame f = probe_frame(spec, rf, pose);
  EXPECT_NEAR((f.capsule.tip - Vec3(0, 0, 0.03)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((f.capsule.back - Vec3(0, 0, -0.02)).norm(), 0.0, 1e-15);
  // tilt swings the tip anteriorly about the entry; an axial offset component is ignored
  pose.tilt = 10 * kDeg;
  pose.offset = Vec3(0.001, 0.002, 0.5);
  f = probe_frame(spec, rf, pose);
  const Vec3 pivot = spec.entry + Vec3(0.001, 0.002, 0);
  EXPECT_NEAR((f.pivot - pivot).norm(), 0.0, 1e-15);
  EXPECT_NEAR((f.capsule.tip - (pivot + 0.06 * Vec3(0, std::sin(10 * kDeg), std::cos(10 * kDeg)))).norm(), 0.0, 1e-15);
  // roll turns the body frame about the axis and leaves the axis alone
  pose.roll = 90 * kDeg;
  const ProbeFrame g = probe_frame(spec, rf, pose);
  EXPECT_NEAR((g.axis() - f.axis()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(g.anterior().dot(f.anterior()), 0.0, 1e-12);
  EXPECT_NEAR((g.rot.transpose() * g.rot - Mat3::Identity()).norm(), 0.0, 1e-14);
}

TEST(ProbeGeometry, CapsuleSignedDistanceIsExact) {
  Capsule c{Vec3(0, 0, 0), Vec3(0, 0, 0.05), Vec3::UnitZ(), 0.05, 0.01};
  EXPECT_NEAR(capsule_signed_distance(c, Vec3(0.013, 0, 0.02)), 0.003, 1e-15);      // side
  EXPECT_NEAR(capsule_signed_distance(c, Vec3(0, 0.004, 0.03)), -0.006, 1e-15);     // inside
  EXPECT_NEAR(capsule_signed_distance(c, Vec3(0, 0, 0.07)), 0.01, 1e-15);           // beyond the tip
  EXPECT_NEAR(capsule_signed_distance(c, Vec3(0.006, 0, 0.058)), 0.0, 1e-15);       // on the tip sphere
  EXPECT_NEAR(capsule_signed_distance(c, Vec3(0, 0, -0.004)), -0.006, 1e-15);       // in the back cap
}

TEST(ProbeNeedleGuide, BiopsyGuideLeavesTheProbeSurfaceAtTheClinicalAngle) {
  ProbeSpec spec;
  spec.guide_angle = 20 * kDeg;
  spec.guide_back = 0.015;
  const RectalFrame rf = rectal_frame(spec);
  ProbePose pose;
  pose.insertion = 0.08;
  pose.tilt = 8 * kDeg;
  const ProbeFrame f = probe_frame(spec, rf, pose);
  const NeedlePath g = biopsy_guide_path(spec, f);
  EXPECT_NEAR(g.direction.norm(), 1.0, 1e-15);
  EXPECT_NEAR(std::acos(g.direction.dot(f.axis())), 20 * kDeg, 1e-12);
  EXPECT_NEAR(capsule_signed_distance(f.capsule, g.entry), 0.0, 1e-15);           // on the surface
  EXPECT_GT(g.direction.dot(f.anterior()), 0.0);                                   // toward the prostate
  EXPECT_NEAR((f.capsule.tip - g.entry).dot(f.axis()), 0.015, 1e-15);
  // rolling the probe by 90 degrees takes the guide with it
  pose.roll = 90 * kDeg;
  const NeedlePath r = biopsy_guide_path(spec, probe_frame(spec, rf, pose));
  EXPECT_NEAR(std::acos(r.direction.dot(f.axis())), 20 * kDeg, 1e-12);
  EXPECT_NEAR((r.entry - g.entry).norm(), std::sqrt(2.0) * spec.radius, 1e-12);
}

TEST(ProbeNeedleGuide, TemplateHolesAre5mmApartParallelToTheProbeAndFixedToTheStepper) {
  ProbeSpec spec;  // defaults: 13 x 13 holes, 5 mm pitch, 30 mm behind the entry
  const RectalFrame rf = rectal_frame(spec);
  ProbePose pose;
  pose.insertion = 0.07;
  const NeedlePath a = template_hole_path(spec, rf, pose, 6, 0);
  const NeedlePath b = template_hole_path(spec, rf, pose, 7, 0);
  const NeedlePath c = template_hole_path(spec, rf, pose, 6, 1);
  EXPECT_NEAR((b.entry - a.entry).norm(), 0.005, 1e-15);
  EXPECT_NEAR((c.entry - a.entry).norm(), 0.005, 1e-15);
  EXPECT_NEAR((c.entry - a.entry).dot(rf.anterior), 0.005, 1e-15);
  // centre column, first row: on the anterior side of the probe axis, 30 mm outside the entry
  EXPECT_NEAR((a.entry - (spec.entry - 0.030 * rf.axial + 0.010 * rf.anterior)).norm(), 0.0, 1e-15);
  const ProbeFrame f = probe_frame(spec, rf, pose);
  EXPECT_NEAR((a.direction - f.axis()).norm(), 0.0, 1e-15);
  // stepping the probe in (insertion) or rolling it does not move the template
  pose.insertion = 0.09;
  pose.roll = 30 * kDeg;
  EXPECT_NEAR((template_hole_path(spec, rf, pose, 6, 0).entry - a.entry).norm(), 0.0, 1e-15);
  // tilting the stepper tilts the needles with the probe
  pose.tilt = 5 * kDeg;
  EXPECT_NEAR((template_hole_path(spec, rf, pose, 3, 4).direction - probe_frame(spec, rf, pose).axis()).norm(), 0.0, 1e-15);
  EXPECT_THROW(template_hole_path(spec, rf, pose, 13, 0), InputError);
  EXPECT_THROW(template_hole_path(spec, rf, pose, 0, -1), InputError);
}

// ---- commands -------------------------------------------------------------------------------

TEST(ProbeCommands, ScriptedMovesFollowASmoothstepAndALaterMoveTakesOver) {
  const std::string y =
      "name: t\nmaterials: {m: {young_kpa: 5}}\ncomponents:\n"
      "  - {name: rectum, material: m, spacing_mm: 6, fill: surface, cylinder: {base_mm: [0,0,-40], radius_mm: 14, length_mm: 80}}\n"
      "probe:\n  radius_mm: 10\n  length_mm: 40\n  entry_mm: [0, 0, -25]\n  pose: {insertion_mm: 40}\n"
      "  limits: {max_speed_mm_s: 200, max_angular_speed_deg_s: 180}\n"
      "  moves:\n    - {ramp_s: [0.1, 0.3], insertion_mm: 50}\n    - {ramp_s: [0.2, 0.4], tilt_deg: 10}\n";
  const ScenarioSpec spec = parse_scenario_text(y, "t.yaml");
  auto m = compile_scenario(spec);
  ProbeTool tool(*spec.probe, *m);
  State s = make_state(*m);
  auto at = [&](double t) {
    s.time = t - 1e-3;
    tool.boundary_conditions(*m, s, 1e-3);
    return tool.pose();
  };
  EXPECT_DOUBLE_EQ(at(0.05).insertion, 0.040);
  EXPECT_NEAR(at(0.15).insertion, 0.040 + 0.010 * 0.15625, 1e-15);  // s = 1/4: 3s^2 - 2s^3
  EXPECT_NEAR(at(0.2).insertion, 0.045, 1e-15);                      // s = 1/2
  // the tilt move starts at 0.2 and the insertion stops where it was
  EXPECT_NEAR(at(0.3).insertion, 0.045, 1e-15);
  EXPECT_NEAR(at(0.3).tilt, 5 * kDeg, 1e-15);
  EXPECT_NEAR(at(0.5).tilt, 10 * kDeg, 1e-15);
  EXPECT_TRUE(tool.reports().empty());
}

TEST(ProbeCommands, FastCommandsAreLengthenedToTheSpeedLimitAndReported) {
  Scene s = make_scene();
  const ProbePose target = pushed(*s.probe, 0.004);
  // 4 mm at 200 mm/s with a smoothstep peak of 1.5x the mean: 30 ms
  const double used = s.probe->move_to(target, 0.0);
  EXPECT_NEAR(used, 1.5 * 0.004 / 0.2, 1e-12);
  ASSERT_EQ(s.probe->reports().size(), 1u);
  EXPECT_NE(s.probe->reports()[0].find("speed limit"), std::string::npos);
  run(s, 31);
  EXPECT_NEAR((s.probe->pose().offset - target.offset).norm(), 0.0, 1e-15);
  // a slow command is taken as given
  EXPECT_DOUBLE_EQ(s.probe->move_to(pushed(*s.probe, 0.0), 0.5), 0.5);
  EXPECT_EQ(s.probe->reports().size(), 1u);
  EXPECT_THROW(s.probe->move_to(pushed(*s.probe, 0.0, 50 * kDeg), 1.0), InputError);
  EXPECT_THROW(s.probe->move_to(pushed(*s.probe, 0.0), -1.0), InputError);
  ProbePose bad = s.probe->pose();
  bad.insertion = std::nan("");
  EXPECT_THROW(s.probe->move_to(bad, 1.0), InputError);
}

// ---- contact ----------------------------------------------------------------------------------

TEST(ProbeContact, PushingMovesTheProstateAwayFromTheRectumMoreForALargerPush) {
  // the rectal wall is 2 mm outside the probe: offsets of 3.5 and 6 mm indent it 1.5 and 4 mm
  double away[2], base_apex[2], force[2];
  const double offsets[2] = {0.0035, 0.006};
  for (int k = 0; k < 2; ++k) {
    Scene s = make_scene();
    const std::vector<Vec3> ref = s.sim->state().x;
    s.probe->move_to(pushed(*s.probe, offsets[k]), 0.0);
    run(s, 80);
    const double at80 = prostate_motion(s, ref).all.mean_vec.y();
    run(s, 20);
    const DisplacementStats d = prostate_motion(s, ref);
    EXPECT_NEAR(d.all.mean_vec.y(), at80, 0.02 * std::abs(at80)) << "not settled";
    away[k] = d.all.mean_vec.y();
    base_apex[k] = d.base.mean_vec.y() / d.apex.mean_vec.y();
    force[k] = s.probe->reaction_force().y();
    EXPECT_LT(s.worst_penetration, kProbePenetrationTolerance);
    EXPECT_GT(s.probe->contact_count(), 0);
    EXPECT_EQ(s.probe->blocked_count(), 0);
    std::printf("push %.1f mm: prostate mean away %.3f mm (max |u| %.3f mm), base/apex %.2f, force %.3f N\n",
                offsets[k] * 1e3, away[k] * 1e3, d.all.max * 1e3, base_apex[k], force[k]);
  }
  EXPECT_GT(away[0], 0.2e-3);
  EXPECT_GT(away[1], 1.5 * away[0]);
  EXPECT_LT(away[1], 0.004);  // moves less than the wall indentation: tissue between deforms
  // a push parallel to the rectum moves base and apex alike (compare the tilt test)
  EXPECT_GT(base_apex[1], 0.6);
  EXPECT_LT(base_apex[1], 1.6);
  // the tissue pushes back on the probe (posteriorly), harder for the larger push
  EXPECT_LT(force[0], 0.0);
  EXPECT_LT(force[1], 1.5 * force[0]);
}

TEST(ProbeContact, TiltingDeformsTheProstateAsymmetrically) {
  // 7 degrees about the anal entry: the tip (50 mm out) rises 6 mm, the apex level ~1.6 mm (less
  // than the 2 mm gap), the base level ~5 mm
  Scene s = make_scene();
  const std::vector<Vec3> ref = s.sim->state().x;
  s.probe->move_to(pushed(*s.probe, 0.0, 7 * kDeg), 0.0);
  run(s, 100);
  const DisplacementStats d = prostate_motion(s, ref);
  std::printf("tilt 7 deg: base %.3f mm, mid %.3f mm, apex %.3f mm anterior; max |u| %.3f mm\n", d.base.mean_vec.y() * 1e3,
              d.mid.mean_vec.y() * 1e3, d.apex.mean_vec.y() * 1e3, d.all.max * 1e3);
  EXPECT_GT(d.base.mean_vec.y(), 0.5e-3);
  EXPECT_GT(d.base.mean_vec.y(), 1.8 * d.apex.mean_vec.y());  // parallel push: ~0.95
  EXPECT_GT(d.mid.mean_vec.y(), d.apex.mean_vec.y());
  EXPECT_LT(s.worst_penetration, kProbePenetrationTolerance);
  // the moment of the contact force about the pivot opposes the tilt (about the lateral axis)
  EXPECT_LT(s.probe->reaction_torque().dot(s.probe->rectal().lateral), 0.0);
}

TEST(ProbeContact, ImposedModeCarriesProstateParticlesWithTheProbe) {
  Scene s = make_scene([](ScenarioSpec& sp) { sp.probe->imposed_mode = true; });
  const Model& m = *s.m;
  const std::vector<Vec3> ref = s.sim->state().x;
  s.probe->move_to(pushed(*s.probe, 0.006), 0.0);
  const Component& P = m.components[m.find_component("prostate")];
  std::vector<uint8_t> was(P.particle_count, 0);
  int max_imposed = 0, checked = 0;
  const double h = m.dt / m.substeps;
  for (int k = 0; k < 100 * m.substeps; ++k) {
    const Vec3 tip_before = s.probe->frame().capsule.tip;
    ASSERT_TRUE(s.sim->step(h)) << s.sim->state().fault.describe(m);
    const State& st = s.sim->state();
    const Vec3 moved = s.probe->frame().capsule.tip - tip_before;  // the push is a translation
    max_imposed = std::max(max_imposed, s.probe->imposed_count());
    for (int i = 0; i < P.particle_count; ++i) {
      const int t = P.first_particle + i;
      const bool now = st.contact[t] == 7;
      // imposed on two substeps in a row: moved exactly as the probe did
      if (now && was[i]) {
        EXPECT_NEAR((st.x[t] - st.x_prev[t] - moved).norm(), 0.0, 1e-15);
        ++checked;
      }
      was[i] = now;
    }
    if (k % m.substeps == m.substeps - 1) s.worst_penetration = std::max(s.worst_penetration, penetration(s));
  }
  EXPECT_GT(max_imposed, 0);
  EXPECT_GT(checked, 100);
  EXPECT_LT(s.worst_penetration, kProbePenetrationTolerance);
  const DisplacementStats d = prostate_motion(s, ref);
  std::printf("imposed mode, push 6 mm: prostate mean away %.3f mm, max |u| %.3f mm, %d particles carried\n",
              d.all.mean_vec.y() * 1e3, d.all.max * 1e3, max_imposed);
  EXPECT_GT(d.all.mean_vec.y(), 0.5e-3);
  EXPECT_LT(d.all.max, 0.01);
}

// The rectal wall made incompressible and emptied to 75 % of its volume over 30 ms: it collapses
// onto the probe, so vertices of a volume-constrained surface sit on it.
Scene emptying_incompressible_rectum() {
  return make_scene(
      [](ScenarioSpec& sp) {
        for (auto& mat : sp.materials)
          if (mat.name == "rectal_wall") mat.incompressible = true;
        sp.filling->schedule = {FillSpec{"rectum", FillSpec::Factor, 0.75, 0.0, 0.03, {}}};
      },
      true);
}

TEST(ProbeContact, EmptyingRectumClosesOnTheProbeWithoutPenetrating) {
  // an incompressible rectum emptied to 75% of its volume collapses onto the probe: the volume
  // projection pulls every free wall particle inward, the contact pushes them back out, and the
  // tool alternates the two so that both hold at the end of each substep
  Scene s = emptying_incompressible_rectum();
  const Model& m = *s.m;
  const int rs = m.components[m.find_component("rectum")].surface;
  for (int i = 0; i < 60; ++i) {
    run(s, 1);
    const double v = surface_volume(m.surfaces[rs], s.sim->state().x);
    ASSERT_NEAR(v / s.sim->state().target_volume[rs], 1.0, 1e-9) << "tick " << i;
  }
  EXPECT_NEAR(s.sim->state().target_volume[rs], 0.75 * m.surfaces[rs].rest_volume, 1e-18);
  EXPECT_GT(s.probe->contact_count(), 50);
  std::printf("rectum at 75%%: %d wall particles on the probe, worst penetration after any tick %.2e mm\n",
              s.probe->contact_count(), s.worst_penetration * 1e3);
  // far inside the 0.1 mm guarantee: the alternation stops below 1 um (without it, this scene
  // leaves wall particles ~13 um inside after the volume projection)
  EXPECT_LT(s.worst_penetration, 1e-6);
  EXPECT_LT(s.probe->max_penetration_seen(), 1e-6);
}

TEST(ProbeContact, TheVolumeAlternationRunsOnlyWithAConstrainedVertexNearTheProbe) {
  // The scene's prostate and bladder are volume-constrained and in the probe's contact set, but
  // at rest no vertex of theirs is within the probe's 1 mm query margin: the engine's volume stage
  // alone keeps them exact, the probe does not alternate, and nothing sits inside the probe.
  {
    Scene s = make_scene();
    const Model& m = *s.m;
    const int ps_ = m.components[m.find_component("prostate")].surface;
    double worst_volume = 0.0;
    for (int i = 0; i < 40; ++i) {
      run(s, 1);
      worst_volume = std::max(worst_volume, std::abs(surface_volume(m.surfaces[ps_], s.sim->state().x) /
                                                         m.surfaces[ps_].rest_volume - 1.0));
    }
    EXPECT_EQ(s.probe->volume_alternations(), 0);
    EXPECT_LT(worst_volume, 1e-12);
    EXPECT_LT(s.worst_penetration, kProbePenetrationTolerance);
  }
  // An incompressible rectum emptying onto the probe puts constrained vertices on it: the probe
  // alternates on every substep of the contact, and they stay out of it (well under 1 um).
  {
    Scene s = emptying_incompressible_rectum();
    run(s, 60);
    EXPECT_GT(s.probe->volume_alternations(), 60);  // 60 ticks of several substeps, most in contact
    EXPECT_LT(s.worst_penetration, 1e-6);
  }
}

TEST(ProbeContact, ProbeAndBladderFillingTogetherStayStableAndExact) {
  Scene s = make_scene(true);
  const Model& m = *s.m;
  const int bs = m.components[m.find_component("bladder")].surface;
  const int ps_ = m.components[m.find_component("prostate")].surface;
  s.probe->move_to(pushed(*s.probe, 0.005, 5 * kDeg), 0.0);
  double worst_volume = 0.0;
  for (int i = 0; i < 160; ++i) {
    run(s, 1);
    const State& st = s.sim->state();
    worst_volume = std::max(worst_volume, std::abs(surface_volume(m.surfaces[bs], st.x) / st.target_volume[bs] - 1.0));
    worst_volume = std::max(worst_volume, std::abs(surface_volume(m.surfaces[ps_], st.x) / m.surfaces[ps_].rest_volume - 1.0));
  }
  EXPECT_LT(worst_volume, 1e-9);
  EXPECT_NEAR(s.sim->state().target_volume[bs], 2.0 * m.surfaces[bs].rest_volume, 1e-15);
  EXPECT_LT(s.worst_penetration, kProbePenetrationTolerance);
  EXPECT_LT(kinetic_energy(m, s.sim->state()), 1e-6);  // settling, not growing
  EXPECT_EQ(s.sim->state().clamp_count, 0);
}

TEST(ProbeContact, SameCommandsGiveBitIdenticalStates) {
  uint64_t h[2];
  for (int k = 0; k < 2; ++k) {
    Scene s = make_scene(true);
    s.probe->move_to(pushed(*s.probe, 0.004, 3 * kDeg), 0.0);
    run(s, 40);
    h[k] = hash_state(s.sim->state());
  }
  EXPECT_EQ(h[0], h[1]);
}

TEST(ProbeContact, StepWithProbeAndFillingDoesNotAllocate) {
  // counting allocator over many substeps with contact (either broad phase: the box by default,
  // FCL's refit + query every substep), volume alternation and filling
  for (ProbeBroadPhase b : {ProbeBroadPhase::Box, ProbeBroadPhase::Fcl}) {
    Scene s = make_scene(true);
    ASSERT_EQ(s.probe->broad_phase(), ProbeBroadPhase::Box);
    s.probe->set_broad_phase(b);
    ASSERT_EQ(s.probe->broad_phase(), b);
    s.probe->move_to(pushed(*s.probe, 0.005, 3 * kDeg), 0.0);
    run(s, 5);
    const long before = test::allocation_count();
    for (int i = 0; i < 30; ++i) ASSERT_TRUE(s.sim->tick());
    EXPECT_EQ(test::allocation_count() - before, 0);
    EXPECT_GT(s.probe->contact_count(), 0);
  }
}

TEST(ProbeContact, FclAndBoxBroadPhasesGiveBitIdenticalStates) {
  // FCL finds the candidates, the analytic projection moves them: the same particles move the
  // same way as with the box over every candidate, so the states hash alike
  uint64_t h[2];
  int tested[2];
  for (int k = 0; k < 2; ++k) {
    Scene s = make_scene(true);
    s.probe->set_broad_phase(k == 0 ? ProbeBroadPhase::Fcl : ProbeBroadPhase::Box);
    s.probe->move_to(pushed(*s.probe, 0.006, 4 * kDeg), 0.0);
    run(s, 60);
    h[k] = hash_state(s.sim->state());
    tested[k] = s.probe->near_count();
    EXPECT_GT(s.probe->contact_count(), 10);
    EXPECT_LT(s.worst_penetration, kProbePenetrationTolerance);
  }
  EXPECT_EQ(h[0], h[1]);
  std::printf("particles tested per substep at the end: FCL %d, box %d\n", tested[0], tested[1]);
}

// ---- bad input --------------------------------------------------------------------------------

std::string with_probe(const std::string& probe_block) {
  return "name: t\nmaterials: {m: {young_kpa: 5}, bone: {young_kpa: 5}}\ncomponents:\n"
         "  - {name: rectum, material: m, spacing_mm: 6, fill: surface, cylinder: {base_mm: [0,0,-40], radius_mm: 12, length_mm: 80}}\n"
         "  - {name: prostate, material: m, spacing_mm: 6, box: {min_mm: [-12, 14, -12], max_mm: [12, 32, 12]}}\n"
         "  - {name: pubis, type: rigid, material: bone, spacing_mm: 6, box: {min_mm: [-12, 40, -12], max_mm: [12, 60, 12]}}\n" +
         probe_block;
}

InputError probe_error(const std::string& yaml) {
  try {
    const ScenarioSpec spec = parse_scenario_text(yaml, "bad.yaml");
    auto m = compile_scenario(spec);
    ProbeTool tool(*spec.probe, *m);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << yaml;
  return InputError("", 0, "", "");
}

TEST(ProbeInput, ProbeOutsideTheRectumInsideTissueOrBoneIsRefusedNamingThePose) {
  const std::string ok = "probe: {radius_mm: 10, length_mm: 40, entry_mm: [0, 0, -28], pose: {insertion_mm: 40}}\n";
  EXPECT_NO_THROW({
    const ScenarioSpec spec = parse_scenario_text(with_probe(ok), "ok.yaml");
    ProbeTool tool(*spec.probe, *compile_scenario(spec));
  });
  // in the prostate, outside the rectal lumen
  InputError e = probe_error(with_probe("probe:\n  entry_mm: [0, 22, -28]\n  radius_mm: 3\n  length_mm: 30\n  pose: {insertion_mm: 30}\n"));
  EXPECT_EQ(e.field(), "probe.pose");
  EXPECT_EQ(e.line(), 11);
  EXPECT_NE(std::string(e.what()).find("outside the rectum"), std::string::npos) << e.what();
  // wider than the rectum: the wall would start inside the probe
  e = probe_error(with_probe("probe: {radius_mm: 14, length_mm: 40, entry_mm: [0, 0, -28], pose: {insertion_mm: 40}}\n"));
  EXPECT_EQ(e.field(), "probe.pose");
  EXPECT_NE(std::string(e.what()).find("inside tissue"), std::string::npos) << e.what();
  // in the pubis (no rectum check asked: contact lists the prostate only and names no rectum)
  const std::string bone =
      "name: t\nmaterials: {m: {young_kpa: 5}}\ncomponents:\n"
      "  - {name: pubis, type: rigid, material: m, spacing_mm: 6, box: {min_mm: [-20, -20, -20], max_mm: [20, 20, 40]}}\n"
      "probe: {radius_mm: 5, length_mm: 20, entry_mm: [0, 0, -10], pose: {insertion_mm: 20}}\n";
  e = probe_error(bone);
  EXPECT_EQ(e.field(), "probe.pose");
  EXPECT_NE(std::string(e.what()).find("bone"), std::string::npos) << e.what();
}

TEST(ProbeInput, BadProbeKeysNameTheField) {
  auto field_of = [](const std::string& block) {
    try {
      parse_scenario_text(with_probe(block), "bad.yaml");
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("<none>");
  };
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], pose: {insertion_mm: 40, tilt_deg: 50}}\n"), "probe.pose.tilt_deg");
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], anterior: [0,0,2], pose: {insertion_mm: 40}}\n"), "probe.anterior");
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], radius_mm: -1, pose: {insertion_mm: 40}}\n"), "probe.radius_mm");
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], pose: {insertion_mm: 40}, colour: red}\n"), "probe.colour");
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], pose: {insertion_mm: 40}, contact: {mode: imposed}}\n"), "probe.contact.mode");
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], pose: {insertion_mm: 40}, contact: {components: [liver]}}\n"),
            "probe.contact.components");
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], pose: {insertion_mm: 40}, moves: [{ramp_s: [1, 0], tilt_deg: 3}]}\n"),
            "probe.moves[0].ramp_s");
  EXPECT_EQ(field_of("probe: {entry_mm: [0,0,0], pose: {insertion_mm: 40}, moves: [{ramp_s: [0, 1]}]}\n"), "probe.moves[0]");
  EXPECT_EQ(field_of("probe: {pose: {insertion_mm: 40}}\n"), "probe.entry_mm");
  // the keys are read in SI
  const ScenarioSpec s = parse_scenario_text(
      with_probe("probe:\n  radius_mm: 9\n  length_mm: 40\n  entry_mm: [0, 0, -28]\n  pose: {insertion_mm: 40, tilt_deg: 4, offset_mm: [0, 2, 0]}\n"
                 "  moves: [{ramp_s: [0.1, 0.2], yaw_deg: -3}]\n  limits: {max_speed_mm_s: 20}\n"
                 "  needle_guide: {angle_deg: 15, back_mm: 12}\n  template: {pitch_mm: 5, cols: 11, rows: 9}\n"),
      "ok.yaml");
  ASSERT_TRUE(s.probe);
  EXPECT_DOUBLE_EQ(s.probe->radius, 0.009);
  EXPECT_DOUBLE_EQ(s.probe->pose.tilt, 4 * kDeg);
  EXPECT_DOUBLE_EQ(s.probe->pose.offset.y(), 0.002);
  EXPECT_DOUBLE_EQ(*s.probe->moves[0].yaw, -3 * kDeg);
  EXPECT_DOUBLE_EQ(s.probe->max_speed, 0.02);
  EXPECT_DOUBLE_EQ(s.probe->guide_angle, 15 * kDeg);
  EXPECT_EQ(s.probe->template_cols, 11);
}

TEST(ProbeContact, DrivingTheProbeIntoBoneIsReportedNotAFault) {
  // rectum, then a rigid block 3 mm anterior of its wall; a 9 mm push reaches the bone
  const std::string y =
      "name: t\ngravity_m_s2: [0, 0, 0]\nmaterials: {m: {young_kpa: 5, damping_1_s: 200}}\ncomponents:\n"
      "  - {name: rectum, material: m, spacing_mm: 6, fill: surface, cylinder: {base_mm: [0,0,-40], radius_mm: 12, length_mm: 80}}\n"
      "  - {name: pubis, type: rigid, material: m, spacing_mm: 6, box: {min_mm: [-12, 15, -12], max_mm: [12, 27, 12]}}\n"
      "constraints:\n  - fix: {component: rectum, region: {box: {min_mm: [-99,-99,-99], max_mm: [99,99,-38]}}}\n"
      "probe:\n  entry_mm: [0, 0, -28]\n  length_mm: 50\n  pose: {insertion_mm: 50}\n  limits: {max_speed_mm_s: 500}\n";
  const ScenarioSpec spec = parse_scenario_text(y, "bone.yaml");
  auto m = compile_scenario(spec);
  Simulation sim(m);
  auto p = std::make_unique<ProbeTool>(*spec.probe, *m);
  ProbeTool* probe = p.get();
  sim.add_tool(std::move(p));
  probe->move_to(pushed(*probe, 0.009), 0.0);
  for (int i = 0; i < 40; ++i) ASSERT_TRUE(sim.tick()) << sim.state().fault.describe(*m);
  EXPECT_GT(probe->blocked_count(), 0);
  EXPECT_GT(probe->blocked_substeps(), 0);
}

}  // namespace
}  // namespace ps
