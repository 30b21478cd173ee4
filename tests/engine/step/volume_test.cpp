// Exact volume projection (paper §3.3): after one projection |V - V0| / V0 <= 1e-10 from large
// deformations, with fixed coordinates left untouched.
#include <gtest/gtest.h>

#include <random>

#include "engine/step/stages.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

TEST(Volume, ProjectionRestoresVolumeFromLargeDeformation) {
  auto m = test::compile_text(test::cube_yaml(40, 10, true, false));
  ASSERT_TRUE(m->surfaces[0].volume_constrained);
  const double V0 = m->surfaces[0].rest_volume;
  EXPECT_NEAR(V0, 0.04 * 0.04 * 0.04, 1e-15);
  std::mt19937 rng(3);
  std::normal_distribution<double> N(0.0, 0.004);
  for (double squash : {0.5, 0.8, 1.3, 2.0}) {
    State s = make_state(*m);
    for (int p = 0; p < m->particle_count(); ++p) {
      const Vec3 r = m->rest_pos[p];
      s.x[p] = Vec3(r.x() * (1 + 0.3 * std::sin(40 * r.z())), r.y() / squash, r.z() * squash) + Vec3(N(rng), N(rng), N(rng));
    }
    const double before = surface_volume(m->surfaces[0], s.x);
    ASSERT_GT(std::abs(before - V0) / V0, 0.05) << "deformation should change the volume";
    ASSERT_TRUE(project_volumes(*m, s));
    const double after = surface_volume(m->surfaces[0], s.x);
    EXPECT_LE(std::abs(after - V0) / V0, 1e-10) << "squash " << squash;
  }
}

TEST(Volume, TargetVolumeCanChange) {
  auto m = test::compile_text(test::cube_yaml(40, 10, true, false));
  State s = make_state(*m);
  s.target_volume[0] = 2.0 * m->surfaces[0].rest_volume;  // bladder doubling
  ASSERT_TRUE(project_volumes(*m, s));
  EXPECT_LE(std::abs(surface_volume(m->surfaces[0], s.x) / s.target_volume[0] - 1.0), 1e-10);
}

TEST(Volume, LockedCoordinatesAreNotMoved) {
  auto m = test::compile_text(test::cube_yaml(40, 10, true, true, 20, "[0, 0, 0]"));
  State s = make_state(*m);
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] *= 1.1;
  for (const FixedParticle& f : m->fixed) s.x[f.particle] = m->rest_pos[f.particle];
  ASSERT_TRUE(project_volumes(*m, s));
  for (const FixedParticle& f : m->fixed) EXPECT_EQ(s.x[f.particle], m->rest_pos[f.particle]);
  EXPECT_LE(std::abs(surface_volume(m->surfaces[0], s.x) / m->surfaces[0].rest_volume - 1.0), 1e-10);
}

}  // namespace
}  // namespace ps
