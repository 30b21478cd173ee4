// A real prostate-shaped mesh (../shared/data/prostate_phantom/prostate.stl, 26.3 cm^3, mm) as a
// volumetric incompressible component: the compiled rest state is an equilibrium, so without
// gravity or loads it stays at rest.
#include <gtest/gtest.h>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/run.h"
#include "engine/step/simulation.h"

namespace ps {
namespace {

TEST(PhantomProstate, StaysAtRestUnloaded) {
  const std::string stl = std::string(PROSTATESIM_SHARED_DATA) + "/prostate_phantom/prostate.stl";
  const std::string yaml =
      "name: phantom_prostate\n"
      "time: {dt_ms: 1, substeps: 8}\n"
      "gravity_m_s2: [0, 0, 0]\n"
      "materials:\n"
      "  prostate: {young_kpa: 40, density_kg_m3: 1050, damping_1_s: 40, incompressible: true}\n"
      "components:\n"
      "  - name: prostate\n"
      "    material: prostate\n"
      "    spacing_mm: 5\n"
      "    mesh: {file: \"" + stl + "\", units: mm}\n";
  const auto model = compile_scenario(parse_scenario_text(yaml, "phantom.yaml"));
  const Model& m = *model;
  ASSERT_GT(m.particle_count(), 100);
  EXPECT_NEAR(m.surfaces[0].rest_volume * 1e6, 26.3, 0.5);   // cm^3, SOURCE/README value
  Simulation sim(model);
  for (int t = 0; t < 200; ++t) ASSERT_TRUE(sim.tick()) << sim.state().fault.describe(m);   // 0.2 s
  EXPECT_LT(max_speed(sim.state()), 1e-9);   // [m/s]
  double moved = 0.0;
  for (int p = 0; p < m.particle_count(); ++p) moved = std::max(moved, (sim.state().x[p] - m.rest_pos[p]).norm());
  EXPECT_LT(moved, 1e-9);   // [m]
  EXPECT_LE(volume_errors(m, sim.state()).at("prostate"), 1e-12);
}

// The hip bone of ../shared/data (units unstated, decimetres plausible; walls thinner than a
// 7 mm grid) imported as a rigid obstacle: the particle count follows the chosen spacing (edge
// collapse, since grid clustering breaks its thin walls), and it becomes one kinematic body.
TEST(SharedBone, ImportsAsARigidComponentAtTheChosenSpacing) {
  const std::string obj = std::string(PROSTATESIM_SHARED_DATA) + "/pelvis_bone/pelvis_f.obj";
  auto yaml = [&](const char* spacing) {
    return std::string("name: bone\n"
                       "time: {dt_ms: 1, substeps: 1}\n"
                       "materials:\n"
                       "  bone: {young_kpa: 1.0e7, density_kg_m3: 1900}\n"
                       "components:\n"
                       "  - {name: hip, type: rigid, kinematic: true, material: bone, fill: surface, spacing_mm: ") +
           spacing + ", mesh: {file: \"" + obj + "\", units: dm}}\n";
  };
  const auto m5 = compile_scenario(parse_scenario_text(yaml("5"), "bone.yaml"));
  const auto m7 = compile_scenario(parse_scenario_text(yaml("7"), "bone.yaml"));
  ASSERT_EQ(m7->rigid_bodies.size(), 1u);
  EXPECT_TRUE(m7->rigid_bodies[0].kinematic);
  // the file has 4884 vertices; 7 mm gives ~1.6k particles, 5 mm more
  EXPECT_LT(m7->particle_count(), 2500);
  EXPECT_GT(m7->particle_count(), 800);
  EXPECT_GT(m5->particle_count(), m7->particle_count());
  EXPECT_NEAR(m7->surfaces[0].rest_volume, 230.77e-6, 0.01 * 230.77e-6);   // volume kept [m^3]
}

}  // namespace
}  // namespace ps
