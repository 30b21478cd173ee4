// A real prostate-shaped mesh (../shared/data/prostate_phantom/prostate.stl, 26.3 cm^3, mm) as a
// volumetric incompressible component: the compiled rest state is an equilibrium, so without
// gravity or loads it stays at rest.
#include <gtest/gtest.h>

#include "engine/mesh/mesh_query.h"
#include "engine/model/material.h"
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
  // the user is told the bone was coarsened by edge collapse, and the rigid bone gets no
  // stiffness-calibration warning (it has no shape memory)
  bool told = false;
  for (const std::string& w : m7->compile_warnings) {
    told = told || w.find("edge collapse") != std::string::npos;
    EXPECT_EQ(w.find("calibrated"), std::string::npos) << w;
  }
  EXPECT_TRUE(told);
}

// A tumour given as a closed mesh (the phantom's internal chamber inner_0.stl, 5.1-5.7 cm^3)
// inside the phantom gland: its own component and material (k_e from E, k_c, k_f), the gland
// filled around it (exclude_inside) and linked to it. The needle tool counts a component named
// "tumour" as tumour in biopsy cores.
TEST(PhantomProstate, ClosedMeshTumourHasItsOwnMaterialInsideTheGland) {
  const std::string d = std::string(PROSTATESIM_SHARED_DATA) + "/prostate_phantom/";
  const std::string yaml =
      "name: phantom_tumour\n"
      "time: {dt_ms: 1, substeps: 8}\n"
      "gravity_m_s2: [0, 0, 0]\n"
      "materials:\n"
      "  gland: {young_kpa: 40, density_kg_m3: 1050, k_c_n: 1.5, k_f_n: 0.5}\n"
      "  cancer: {young_kpa: 100, density_kg_m3: 1050, k_c_n: 2.5, k_f_n: 0.8}\n"
      "components:\n"
      "  - {name: tumour, material: cancer, spacing_mm: 4, mesh: {file: \"" + d + "inner_0.stl\", units: mm}}\n"
      "  - {name: prostate, material: gland, spacing_mm: 4, mesh: {file: \"" + d + "prostate.stl\", units: mm}, exclude_inside: [tumour]}\n"
      "links:\n"
      "  - {a: prostate, b: tumour, distance_mm: 5}\n";
  const auto model = compile_scenario(parse_scenario_text(yaml, "phantom_tumour.yaml"));
  const Model& m = *model;
  const Component& t = m.components[m.find_component("tumour")];
  const Component& g = m.components[m.find_component("prostate")];
  ASSERT_GT(t.particle_count, 20);
  for (int p = t.first_particle; p < t.first_particle + t.particle_count; ++p) {
    EXPECT_DOUBLE_EQ(m.k_e[p], shape_memory_stiffness(100e3, 4e-3));
    EXPECT_DOUBLE_EQ(m.k_c[p], 2.5);
    EXPECT_DOUBLE_EQ(m.k_f[p], 0.8);   // [N per mm of shaft]
  }
  EXPECT_DOUBLE_EQ(m.k_e[g.first_particle], shape_memory_stiffness(40e3, 4e-3));
  // no gland particle inside the tumour's surface
  TriMesh ts;
  ts.vertices = m.rest_pos;
  ts.faces = m.surfaces[t.surface].faces;
  const MeshQuery q(ts);
  for (int p = g.first_particle; p < g.first_particle + g.particle_count; ++p) ASSERT_FALSE(q.inside(m.rest_pos[p])) << p;
  EXPECT_NEAR(signed_volume(ts) * 1e6, 5.4, 0.5);   // cm^3 (README: 5.1-5.7)
}

}  // namespace
}  // namespace ps
