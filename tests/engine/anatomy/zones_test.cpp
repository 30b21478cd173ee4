// Prostate zone classification (engine/anatomy/zones.h) on a box frame and on the default gland.
#include "engine/anatomy/zones.h"

#include <gtest/gtest.h>

#include <map>

#include "engine/anatomy/pelvis.h"
#include "engine/mesh/mesh_query.h"

namespace ps::anatomy {
namespace {

// gland 40 x 30 x 36 mm centred at the origin, 8 mm shells
ProstateFrame frame() {
  ProstateFrame f;
  f.lo = Vec3(-20e-3, -15e-3, -18e-3);
  f.hi = Vec3(20e-3, 15e-3, 18e-3);
  f.peripheral_depth = 8e-3;
  return f;
}

TEST(Zones, LevelsAreCraniocaudalThirds) {
  EXPECT_EQ(classify_prostate_point(Vec3(0, 0, -10e-3), 10e-3, frame()).level, ProstateLevel::Apex);
  EXPECT_EQ(classify_prostate_point(Vec3(0, 0, -5e-3), 10e-3, frame()).level, ProstateLevel::Mid);
  EXPECT_EQ(classify_prostate_point(Vec3(0, 0, 5e-3), 10e-3, frame()).level, ProstateLevel::Mid);
  EXPECT_EQ(classify_prostate_point(Vec3(0, 0, 7e-3), 10e-3, frame()).level, ProstateLevel::Base);
}

TEST(Zones, SidesFollowThePatientFrame) {
  // RAS: +x is the patient's right
  EXPECT_EQ(classify_prostate_point(Vec3(3e-3, 0, 0), 10e-3, frame()).side, ProstateSide::Right);
  EXPECT_EQ(classify_prostate_point(Vec3(-3e-3, 0, 0), 10e-3, frame()).side, ProstateSide::Left);
  EXPECT_FALSE(classify_prostate_point(Vec3(9e-3, 0, 0), 10e-3, frame()).lateral);
  EXPECT_TRUE(classify_prostate_point(Vec3(11e-3, 0, 0), 1e-3, frame()).lateral);
  EXPECT_TRUE(classify_prostate_point(Vec3(-11e-3, 0, 0), 1e-3, frame()).lateral);
}

TEST(Zones, PeripheralIsThePosteriorShell) {
  EXPECT_EQ(classify_prostate_point(Vec3(0, -12e-3, 0), 3e-3, frame()).zone, ProstateZone::Peripheral);
  EXPECT_EQ(classify_prostate_point(Vec3(0, -2e-3, 0), 9e-3, frame()).zone, ProstateZone::Transition);
  EXPECT_EQ(classify_prostate_point(Vec3(18e-3, 5e-3, 0), 2e-3, frame()).zone, ProstateZone::Peripheral);  // lateral horn
  EXPECT_EQ(classify_prostate_point(Vec3(0, 12e-3, 0), 3e-3, frame()).zone, ProstateZone::Anterior);
  const ProstateZoneTag t = classify_prostate_point(Vec3(-14e-3, -10e-3, 8e-3), 2e-3, frame());
  EXPECT_EQ(zone_label(t), "left base lateral (peripheral)");
  const auto idx = zone_tag_indices(t);
  EXPECT_STREQ(kZoneTagNames[idx[0]], "base");
  EXPECT_STREQ(kZoneTagNames[idx[1]], "left");
  EXPECT_STREQ(kZoneTagNames[idx[2]], "lateral");
  EXPECT_STREQ(kZoneTagNames[idx[3]], "peripheral");
}

TEST(Zones, DefaultGlandHasEveryTwelveCoreSectorInItsPeripheralZone) {
  const TriMesh gland = generate_anatomy().prostate;
  const MeshQuery q(gland);
  const ProstateFrame f = ProstateFrame::from_points(gland.vertices, 8e-3);
  std::map<std::string, int> pz;
  int inside = 0, peripheral = 0;
  for (double x = -24e-3; x <= 24e-3; x += 1e-3)
    for (double y = -15e-3; y <= 17e-3; y += 1e-3)
      for (double z = -22e-3; z <= 19e-3; z += 1e-3) {
        const Vec3 p(x, y, z);
        if (!q.inside(p)) continue;
        ++inside;
        const ProstateZoneTag t = classify_prostate_point(p, q.distance(p), f);
        if (t.zone != ProstateZone::Peripheral) continue;
        ++peripheral;
        ++pz[zone_label(t)];
      }
  EXPECT_EQ(pz.size(), 12u);   // {apex, mid, base} x {right, left} x {medial, lateral}
  // the peripheral zone holds the larger part of the glandular tissue (McNeal: ~70 %)
  EXPECT_GT(peripheral, inside / 2);
  EXPECT_LT(peripheral, inside * 9 / 10);
}

}  // namespace
}  // namespace ps::anatomy
