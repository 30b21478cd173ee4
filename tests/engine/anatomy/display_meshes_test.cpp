// Shapes drawn and imaged but not simulated (engine/anatomy/display_meshes.h): config/biopsy.yaml
// gets both seminal vesicles and the pubic bone from the files beside its gland's mesh; every
// carried vertex sits where the file puts it at rest and moves with the particles that carry it;
// a scenario without the files gets none.
#include "engine/anatomy/display_meshes.h"

#include <gtest/gtest.h>

#include "engine/anatomy/pelvis.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "tests/engine/test_scenes.h"

namespace ps::anatomy {
namespace {

TEST(DisplayMeshes, BiopsySceneCarriesBothVesiclesAndThePubicBone) {
  const ScenarioSpec spec = parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
  const auto model = compile_scenario(spec);
  const std::vector<DisplayMesh> d = display_meshes_for_scenario(spec, *model);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].kind, DisplayMesh::SeminalVesicle);
  EXPECT_EQ(d[1].kind, DisplayMesh::SeminalVesicle);
  EXPECT_NE(d[0].name, d[1].name);  // right and left
  EXPECT_EQ(d[2].kind, DisplayMesh::Bone);
  const Anatomy a = generate_anatomy();
  EXPECT_EQ(d[0].mesh.vertices.size() + d[1].mesh.vertices.size(), a.seminal_vesicles.vertices.size());
  std::vector<float> x(3 * model->rest_pos.size()), moved(x.size());
  for (size_t p = 0; p < model->rest_pos.size(); ++p)
    for (int k = 0; k < 3; ++k) x[3 * p + k] = static_cast<float>(model->rest_pos[p][k]), moved[3 * p + k] = x[3 * p + k] + (k == 1 ? 0.004f : 0.0f);
  for (const DisplayMesh& m : d) {
    ASSERT_EQ(m.carriers.size(), m.mesh.vertices.size());
    double worst_rest = 0.0, worst_shift = 0.0;
    for (size_t v = 0; v < m.mesh.vertices.size(); ++v) {
      worst_rest = std::max(worst_rest, (m.vertex(x.data(), v) - m.mesh.vertices[v]).norm());
      worst_shift = std::max(worst_shift, (m.vertex(moved.data(), v) - m.mesh.vertices[v] - Vec3(0, 0.004, 0)).norm());
      for (int k = 0; k < 4; ++k) {
        const Component& c = model->components[model->component_of[m.carriers[v][k]]];
        if (m.kind == DisplayMesh::Bone) EXPECT_EQ(c.role, Role::Bone);
        else EXPECT_NE(c.kind, ComponentKind::Rigid);
      }
    }
    EXPECT_LT(worst_rest, 1e-6) << m.name;   // float positions: ~0.1 um
    EXPECT_LT(worst_shift, 1e-6) << m.name;  // a translation of the tissue moves the shape with it
  }
}

TEST(DisplayMeshes, NoneWithoutTheFiles) {
  const ScenarioSpec spec = parse_scenario_text(test::cube_yaml(), "cube.yaml");
  const auto model = compile_scenario(spec);
  EXPECT_TRUE(display_meshes_for_scenario(spec, *model).empty());
}

}  // namespace
}  // namespace ps::anatomy
