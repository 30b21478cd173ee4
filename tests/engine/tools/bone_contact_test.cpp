// Rigid bone stops the needle tip (FCL against the bone surface), with an event saying where.
#include "engine/tools/bone_contact.h"

#include <gtest/gtest.h>

#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps {
namespace {

TEST(BoneContact, DistanceToARigidBoxSurface) {
  test::BlockOptions o;
  o.extra_components = "  - {name: pubis, type: rigid, material: bone, spacing_mm: 4, box: {min_mm: [-12, -12, -40], max_mm: [12, 12, -28]}}\n";
  auto s = test::make_needle_scene(test::block_yaml(o, test::vertical_needle("n", 1.3, 0.9, "[[0, 0]]")));
  BoneContact bone(*s.model);
  ASSERT_EQ(bone.bone_count(), 1);
  Vec3 q;
  int comp = -1;
  const double d = bone.distance(s.sim->state(), Vec3(1e-3, 1e-3, -25e-3), 0.5e-3, 5e-3, &q, &comp);
  EXPECT_NEAR(d, 2.5e-3, 1e-9);
  EXPECT_NEAR(q.z(), -28e-3, 1e-9);
  EXPECT_EQ(s.model->components[comp].name, "pubis");
  EXPECT_TRUE(std::isinf(bone.distance(s.sim->state(), Vec3(0, 0, 0.1), 0.5e-3, 5e-3, nullptr, nullptr)));
}

TEST(BoneContact, NeedleIsStoppedOnTheBoneWithAnEvent) {
  test::BlockOptions o;
  o.young_kpa = 15;
  o.extra_components = "  - {name: pubis, type: rigid, material: bone, spacing_mm: 4, box: {min_mm: [-12, -12, -40], max_mm: [12, 12, -28]}}\n";
  // commanded 38 mm deep: 9 mm into the bone
  auto s = test::make_needle_scene(test::block_yaml(o, test::vertical_needle("n", 1.3, 0.9, "[[0, 0], [1.2, 38]]")));
  for (int i = 0; i < 1600; ++i) ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
  const NeedleReadout& r = s.tool->readout(0);
  const double radius = 0.5 * s.tool->spec(0).diameter;
  EXPECT_NEAR(r.tip.z(), -28e-3 + radius, 0.1e-3) << "tip rests on the bone surface";
  EXPECT_EQ(r.phase, NeedlePhase::Blocked);
  EXPECT_LT(r.coupling_force.z(), -10.0) << "the hand feels the bone: coupling stretched ~9 mm";
  const auto ev = s.tool->events().snapshot();
  const auto it = std::find_if(ev.begin(), ev.end(), [](auto& e) { return e.kind == NeedleEventKind::BoneHit; });
  ASSERT_NE(it, ev.end());
  EXPECT_EQ(s.model->components[it->component].name, "pubis");
  EXPECT_NEAR(it->position.z(), -28e-3, 1e-6);
  EXPECT_NEAR(it->position.x(), 1.3e-3, 0.2e-3);
  EXPECT_EQ(std::count_if(ev.begin(), ev.end(), [](auto& e) { return e.kind == NeedleEventKind::BoneHit; }), 1)
      << "one event per contact";
  for (int p = 0; p < s.model->particle_count(); ++p) ASSERT_TRUE(s.sim->state().x[p].allFinite());
}

}  // namespace
}  // namespace ps
