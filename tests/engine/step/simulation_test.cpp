// Whole-step behaviour: damped settling, determinism, long-run robustness, fault reporting and
// no allocation inside step().
#include "engine/step/simulation.h"

#include <gtest/gtest.h>

#include "engine/sim/run.h"
#include "engine/step/stages.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

TEST(Simulation, DampedCubeOnFixedBaseComesToRestWithEnergyGoingDown) {
  auto m = test::compile_text(test::cube_yaml(40, 10, false, true, 30));
  Simulation sim(m);
  ASSERT_GT(m->k_e[0], 0.0);
  // total energy = kinetic + gravitational + shape-memory (attractors evaluated at the current
  // positions on a copy); the default force is its exact gradient, so with damping it may only
  // go down
  auto energy = [&] {
    State s = sim.state();
    add_shape_memory_forces(*m, s);
    double e = kinetic_energy(*m, s);
    for (int p = 0; p < m->particle_count(); ++p) {
      e -= m->mass[p] * m->gravity.dot(s.x[p]);
      e += 0.5 * m->k_e[p] * (s.attractor[p] - s.x[p]).squaredNorm();
    }
    return e;
  };
  double peak_ke = 0;
  for (int i = 0; i < 200; ++i) { ASSERT_TRUE(sim.tick()); peak_ke = std::max(peak_ke, kinetic_energy(*m, sim.state())); }
  double prev = energy();
  int rises = 0;
  for (int block = 0; block < 30; ++block) {
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim.tick());
    const double e = energy();
    if (e > prev + 1e-12 * std::abs(prev)) ++rises;
    prev = e;
  }
  EXPECT_EQ(rises, 0) << "total energy rose in a damped run";
  const double ke = kinetic_energy(*m, sim.state());
  EXPECT_LT(ke, 1e-6 * peak_ke) << "not at rest after 3.2 s";
  // it sags under gravity but stays near its rest shape
  double sag = 0;
  for (int p = 0; p < m->particle_count(); ++p) sag = std::min(sag, sim.state().x[p].z() - m->rest_pos[p].z());
  EXPECT_LT(sag, -1e-5);
  EXPECT_GT(sag, -0.02);  // well under half the 40 mm height (accuracy is validate's job)
}

TEST(Simulation, SameScenarioGivesBitIdenticalState) {
  const std::string y = test::cube_yaml(40, 10, true, true, 5);
  uint64_t h[2];
  for (int run = 0; run < 2; ++run) {
    Simulation sim(test::compile_text(y));
    for (int i = 0; i < 500; ++i) ASSERT_TRUE(sim.tick());
    h[run] = hash_state(sim.state());
  }
  EXPECT_EQ(h[0], h[1]);
}

TEST(Simulation, NoAllocationInsideStepWithStrainMemory) {
  Simulation sim(test::compile_text(
      "name: t\nmaterials:\n  gel: {young_kpa: 10, incompressible: true, model: strain}\ncomponents:\n"
      "  - {name: b, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n"
      "constraints:\n  - fix: {component: b, region: {box: {min_mm: [-1,-1,-1], max_mm: [41,41,0.5]}}}\n"));
  ASSERT_NE(std::find(sim.pipeline().begin(), sim.pipeline().end(), Stage::StrainMemory), sim.pipeline().end());
  ASSERT_TRUE(sim.tick());  // warm
  const long before = test::allocation_count();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim.tick());
  EXPECT_EQ(test::allocation_count() - before, 0);
}

TEST(Simulation, NoAllocationInsideStep) {
  Simulation sim(test::compile_text(test::cube_yaml(40, 10, true, true, 5)));
  ASSERT_TRUE(sim.tick());  // warm
  const long before = test::allocation_count();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim.tick());
  EXPECT_EQ(test::allocation_count() - before, 0);
}

TEST(Simulation, PipelineSkipsStagesTheSceneDoesNotNeed) {
  Simulation plain(test::compile_text(test::cube_yaml(40, 10, false, false)));
  for (Stage s : plain.pipeline()) {
    EXPECT_NE(s, Stage::Volume);
    EXPECT_NE(s, Stage::RigidForces);
    EXPECT_NE(s, Stage::LocalConstraints);
  }
  Simulation vol(test::compile_text(test::cube_yaml(40, 10, true, true)));
  EXPECT_NE(std::find(vol.pipeline().begin(), vol.pipeline().end(), Stage::Volume), vol.pipeline().end());
}

TEST(Simulation, PipelineRunsInStageOrder) {
  // the Stage enum lists the stages in the order a substep runs them; every pipeline keeps it
  const std::string scenes[] = {
      test::cube_yaml(40, 10, true, true, 5),
      "name: t\nmaterials:\n  gel: {young_kpa: 10, incompressible: true, model: strain}\ncomponents:\n"
      "  - {name: b, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n"
      "constraints:\n  - fix: {component: b, region: {box: {min_mm: [-1,-1,-1], max_mm: [41,41,0.5]}}}\n"};
  for (const std::string& y : scenes) {
    Simulation sim(test::compile_text(y));
    const auto& pl = sim.pipeline();
    ASSERT_GE(pl.size(), 4u);
    for (size_t i = 1; i < pl.size(); ++i)
      EXPECT_LT(static_cast<int>(pl[i - 1]), static_cast<int>(pl[i])) << stage_name(pl[i - 1]) << " before " << stage_name(pl[i]);
    EXPECT_EQ(pl.back(), Stage::Check);  // no tools: the check ends the substep
  }
}

TEST(Simulation, BlowUpStopsWithParticleAndTime) {
  // raw stiffness far beyond the stable limit with substeps pinned: must fault, not NaN silently
  ScenarioSpec spec = parse_scenario_text(test::cube_yaml(40, 10, false, true, 0), "blow.yaml");
  spec.materials[0].k_e = 1e9;
  auto model = std::const_pointer_cast<Model>(compile_scenario(spec));
  model->substeps = 1;  // defeat the automatic substepping on purpose
  Simulation sim(model);
  bool ok = true;
  for (int i = 0; i < 2000 && ok; ++i) ok = sim.tick();
  ASSERT_FALSE(ok);
  const std::string msg = sim.state().fault.describe(*model);
  EXPECT_NE(msg.find("particle"), std::string::npos) << msg;
  EXPECT_NE(msg.find("t="), std::string::npos) << msg;
  EXPECT_FALSE(sim.tick()) << "a faulted simulation must not advance";
}

TEST(Simulation, AutomaticSubstepsRespectTheStabilityLimit) {
  ScenarioSpec spec = parse_scenario_text(test::cube_yaml(40, 10, false, true, 0), "stiff.yaml");
  spec.materials[0].k_e = 1e6;
  auto m = compile_scenario(spec);
  EXPECT_GT(m->substeps, 1);
  EXPECT_LE(m->dt / m->substeps, 0.9 * m->stable_dt_estimate * (1 + 1e-12));
  EXPECT_FALSE(m->compile_warnings.empty());
  Simulation sim(m);
  for (int i = 0; i < 300; ++i) ASSERT_TRUE(sim.tick()) << sim.state().fault.describe(*m);
}

}  // namespace
}  // namespace ps
