// Virtual tissue particle weights (AffineAnchor): affine-reproducing, linear weights with enough
// non-collinear particles (no stiffness of their own under a held force), translation-only
// fallback with fewer, force continuity on
// re-anchoring, momentum-conserving reaction; and the fallback inside a running needle.
#include "engine/tools/needle/needle_anchor.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps {
namespace {

std::vector<Vec3> cloud() {
  return {Vec3(0, 0, 0), Vec3(2e-3, 0, 0.3e-3), Vec3(0, 2e-3, -0.2e-3), Vec3(0.1e-3, 0.2e-3, 2e-3), Vec3(2e-3, 2e-3, 1e-3),
          Vec3(-1e-3, 1e-3, 1e-3)};
}

const Vec3 kInside(0.7e-3, 0.6e-3, 0.5e-3);  // a point among the cloud's particles

// An anchor at kInside on all six particles of cloud() (x).
AffineAnchor anchor_in_cloud(const std::vector<Vec3>& x) {
  const int ids[] = {0, 1, 2, 3, 4, 5};
  AffineAnchor a;
  a.build(kInside, ids, 6, x, kInside);
  return a;
}

TEST(AffineAnchor, FullCoordinatesReproduceThePointAndFollowRigidMotion) {
  std::vector<Vec3> x = cloud();
  const Vec3 X = kInside;
  const AffineAnchor a = anchor_in_cloud(x);
  ASSERT_TRUE(a.rotational);
  EXPECT_LT((a.evaluate(x) - X).norm(), 1e-15);
  EXPECT_LT(a.offset.norm(), 1e-12) << "the weights alone reproduce the point";
  double wsum = 0;
  for (int i = 0; i < a.count; ++i) wsum += a.w[i];
  EXPECT_NEAR(wsum, 1.0, 1e-12);
  // rigid rotation + translation of the particles carries the attractor along exactly
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 t(1e-3, -2e-3, 0.5e-3);
  for (Vec3& p : x) p = R * p + t;
  EXPECT_LT((a.evaluate(x) - (R * X + t)).norm(), 1e-12);
}

TEST(AffineAnchor, IsAffineAndLinearSoAHeldForceAddsNoStiffnessOfItsOwn) {
  // The paper's coordinates add beta n/|n| terms: P* is then nonlinear in x and a stuck node's
  // friction force F adds F . d2P*/dx2 to the tissue, a stiffness the coupling bound cannot scale
  // away (a prostate particle beside the biopsy track runs away, docs/robustness.md "The needle's
  // virtual particles"). The weights reproduce affine motion and do not depend on the positions
  // after the build.
  const std::vector<Vec3> x = cloud();
  const Vec3 X = kInside;
  const AffineAnchor a = anchor_in_cloud(x);
  ASSERT_TRUE(a.rotational);
  // a general affine map (stretch and shear, not only a rotation) carries the attractor along
  Mat3 A;
  A << 1.2, 0.3, -0.1, 0.05, 0.8, 0.2, -0.15, 0.1, 1.1;
  const Vec3 t(1e-3, -2e-3, 0.5e-3);
  std::vector<Vec3> y = x;
  for (Vec3& p : y) p = A * p + t;
  EXPECT_LT((a.evaluate(y) - (A * X + t)).norm(), 1e-15);
  // linear: the reaction to a held force is the same wherever the particles are, so its
  // derivative (a stiffness) is zero; and the attractor moves by sum w_a dx_a exactly
  const Vec3 F(0.3, -0.2, 0.6);
  std::vector<Vec3> f0(x.size(), Vec3::Zero()), f1(x.size(), Vec3::Zero());
  a.add_reaction(f0, x, F);
  std::vector<Vec3> z = x;
  z[1] += Vec3(0.4e-3, -0.3e-3, 0.2e-3);
  z[4] += Vec3(-0.2e-3, 0.5e-3, 0.1e-3);
  a.add_reaction(f1, z, F);
  for (size_t p = 0; p < x.size(); ++p) EXPECT_EQ(f0[p], f1[p]) << p;
  const Vec3 moved = a.w[1] * (z[1] - x[1]) + a.w[4] * (z[4] - x[4]);
  EXPECT_LT((a.evaluate(z) - a.evaluate(x) - moved).norm(), 1e-18);
}

TEST(AffineAnchor, ParticlesInAPlaneReproduceTheInPlaneMotionAndCarryTheNormalOffset) {
  // a node 1 mm off a wall held by four wall particles (plane z = 0): weights sum to 1 (a
  // translation of the wall carries the attractor exactly) and an in-plane stretch of the wall
  // moves it as it moves the point below it
  std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(3e-3, 0, 0), Vec3(0, 3e-3, 0), Vec3(3e-3, 3e-3, 0)};
  const int ids[] = {0, 1, 2, 3};
  const Vec3 X(1e-3, 2e-3, 1e-3);
  AffineAnchor a;
  a.build(X, ids, 4, x, X);
  ASSERT_TRUE(a.rotational);
  double wsum = 0;
  for (int i = 0; i < a.count; ++i) wsum += a.w[i];
  EXPECT_NEAR(wsum, 1.0, 1e-14);
  EXPECT_LT((a.offset - Vec3(0, 0, 1e-3)).norm(), 1e-15) << "the distance from the wall is the offset";
  std::vector<Vec3> y = x;
  for (Vec3& p : y) p = Vec3(1.5 * p.x() + 0.2 * p.y(), 0.9 * p.y(), 0) + Vec3(0.3e-3, -0.1e-3, 0.4e-3);
  const Vec3 expected = Vec3(1.5 * X.x() + 0.2 * X.y(), 0.9 * X.y(), 1e-3) + Vec3(0.3e-3, -0.1e-3, 0.4e-3);
  EXPECT_LT((a.evaluate(y) - expected).norm(), 1e-15);
}

TEST(AffineAnchor, FewerThanThreeNonCollinearParticlesFallBackToTranslation) {
  // one particle: rigid attachment; two, or three on a line: no valid triplet
  for (int n : {1, 2, 3}) {
    std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(2e-3, 0, 0), Vec3(4e-3, 0, 0)};
    const int ids[] = {0, 1, 2};
    const Vec3 X(1e-3, 1e-3, 0);
    AffineAnchor a;
    a.build(X, ids, n, x, X);
    ASSERT_TRUE(a.valid());
    EXPECT_FALSE(a.rotational) << n;
    EXPECT_LT((a.evaluate(x) - X).norm(), 1e-15);
    for (Vec3& p : x) p += Vec3(0.5e-3, -1e-3, 2e-3);  // the tissue translates
    EXPECT_LT((a.evaluate(x) - (X + Vec3(0.5e-3, -1e-3, 2e-3))).norm(), 1e-15) << n;
  }
}

TEST(AffineAnchor, APointOutsideItsParticlesTakesTheTranslationFormWithBoundedWeights) {
  // A node beside the hole in a wall: three wall particles (a 3 mm triangle in the plane z = 0)
  // all on one side of it, 5 mm away. Their discrete coordinates extrapolate (weights of
  // several units of either sign), and the spring's reaction would be amplified on one light
  // particle; the anchor takes the translation form instead: weights in [0, 1] summing to 1.
  const std::vector<Vec3> x = {Vec3(5e-3, 0, 0), Vec3(8e-3, 0, 0), Vec3(6.5e-3, 2.6e-3, 0)};
  const int ids[] = {0, 1, 2};
  const Vec3 X(0, -1e-3, 1e-3);
  AffineAnchor a;
  a.build(X, ids, 3, x, X);
  ASSERT_TRUE(a.valid());
  EXPECT_FALSE(a.rotational);
  double wsum = 0;
  for (int i = 0; i < a.count; ++i) {
    EXPECT_GE(a.w[i], 0.0);
    EXPECT_LE(a.w[i], 1.0);
    wsum += a.w[i];
  }
  EXPECT_NEAR(wsum, 1.0, 1e-12);
  EXPECT_LT((a.evaluate(x) - X).norm(), 1e-15);
  // the same three particles around a point inside their triangle keep the affine weights
  AffineAnchor b;
  const Vec3 Y(6.5e-3, 0.9e-3, 0.4e-3);
  b.build(Y, ids, 3, x, Y);
  EXPECT_TRUE(b.rotational);
  for (int i = 0; i < b.count; ++i) EXPECT_LE(std::abs(b.w[i] - 1.0 / 3.0), 1.0 / 3.0 + kAnchorWeightMargin);
}

TEST(AffineAnchor, RebuildingKeepsTheAttractorAndTheReactionConservesMomentum) {
  std::vector<Vec3> x = cloud();
  const int ids[] = {0, 1, 2, 3, 4, 5};
  const Vec3 X(0.7e-3, 0.6e-3, 0.5e-3);
  AffineAnchor a;
  a.build(X, ids, 4, x, X);
  x[1] += Vec3(0.3e-3, 0.1e-3, -0.2e-3);  // deform
  const Vec3 before = a.evaluate(x);
  a.build(X, ids + 2, 4, x, before);   // other particles, attractor kept
  EXPECT_LT((a.evaluate(x) - before).norm(), 1e-15);
  std::vector<Vec3> f(x.size(), Vec3::Zero());
  const Vec3 F(0.1, -0.2, 0.05);
  a.add_reaction(f, x, F);
  Vec3 sum = Vec3::Zero();
  for (const Vec3& v : f) sum += v;
  EXPECT_LT((sum + F).norm(), 1e-12) << "tissue receives exactly -F";
}

TEST(NeedleFriction, ZonesWithOneOrTwoParticlesUseTheTranslationFallbackAndStillHold) {
  // needle exactly on a lattice column with friction zones smaller than the spacing: each node
  // zone holds the one or two column particles only (collinear): translation-only anchors
  test::BlockOptions o;
  o.young_kpa = 15;
  auto s = test::make_needle_scene(test::block_yaml(
      o, test::vertical_needle("n", 0, 0, "[[0, 0], [0.8, 14], [1.2, 14], [1.8, 11]]",
                               "      friction_radius_mm: 2.5\n      cutting_radius_mm: 4\n")));
  ASSERT_FALSE(s.tool->warnings().empty()) << "a friction radius under the spacing is warned about";
  for (int i = 0; i < 1200; ++i) ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
  int engaged = 0, fallback = 0;
  for (int j = 0; j < 8; ++j) {
    const auto z = s.tool->zone_particles(0, j);
    if (z.empty()) continue;
    ++engaged;
    EXPECT_LE(z.size(), 2u) << "node " << j;
    fallback += !s.tool->node_anchor_rotational(0, j);
  }
  EXPECT_GE(engaged, 3);
  EXPECT_EQ(fallback, engaged);
  EXPECT_GT(s.tool->readout(0).friction_force, 0.05) << "held still: static friction holds the tissue";
  // pulled back: still finite, friction opposes the pull
  for (int i = 0; i < 600; ++i) ASSERT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
  EXPECT_LT(s.tool->readout(0).friction_force, 0.0);
  EXPECT_LT(max_speed(s.sim->state()), 1.0);
}

}  // namespace
}  // namespace ps
