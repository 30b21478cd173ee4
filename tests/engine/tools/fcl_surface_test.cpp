// FCL surface layer: the triangles FCL's traversal returns against a capsule are exactly those
// with a corner inside it (checked against every triangle by brute force), they follow the
// vertices after a refit, and neither refit nor query allocates.
#include "engine/tools/fcl_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/tools/probe/probe_geometry.h"
#include "tests/engine/counting_allocator.h"

namespace ps {
namespace {

// n x n squares of side h in the plane z = 0, two triangles each; vertex (i, j) is particle
// j * (n + 1) + i.
struct Grid {
  std::vector<Vec3> x;
  std::vector<std::array<int, 3>> faces;
};
Grid grid(int n, double h) {
  Grid g;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) g.x.emplace_back(i * h, j * h, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      g.faces.push_back({a, b, d});
      g.faces.push_back({a, d, c});
    }
  return g;
}

// Deepest corner of a triangle relative to the capsule surface (negative inside) [m].
double corner_gap(const Grid& g, const std::array<int, 3>& f, const Capsule& c) {
  double best = 1e300;
  for (int p : f) best = std::min(best, capsule_signed_distance(c, g.x[p]));
  return best;
}

Capsule capsule(const Vec3& a, const Vec3& b, double r) {
  Capsule c;
  c.back = a;
  c.tip = b;
  c.length = (b - a).norm();
  c.dir = (b - a) / c.length;
  c.radius = r;
  return c;
}

TEST(FclSurface, CapsuleHitsAreTheTrianglesWithinItsRadius) {
  Grid g = grid(12, 0.005);  // 60 mm square, 5 mm triangles
  FclSurfaceContact fcl(g.faces, g.x);
  // a probe lying 3 mm above the plane, radius 4 mm (1 mm into it), tilted across the grid
  const Capsule c = capsule(Vec3(0.012, 0.010, 0.003), Vec3(0.045, 0.040, 0.006), 0.004);
  const int n = fcl.collide_capsule(c.back, c.tip, c.radius);
  std::vector<int> got = fcl.hits();
  std::sort(got.begin(), got.end());
  ASSERT_EQ(static_cast<int>(got.size()), n);
  int clear_in = 0, clear_out = 0;
  for (int f = 0; f < static_cast<int>(g.faces.size()); ++f) {
    const double gap = corner_gap(g, g.faces[f], c);
    const bool hit = std::binary_search(got.begin(), got.end(), f);
    if (gap < 0.0) { EXPECT_TRUE(hit) << "triangle " << f << " has a corner " << -gap << " m inside"; ++clear_in; }
    else { EXPECT_FALSE(hit) << "triangle " << f << " is " << gap << " m clear"; ++clear_out; }
  }
  EXPECT_GT(clear_in, 5);
  EXPECT_GT(clear_out, 200);
}

TEST(FclSurface, RefitFollowsTheVerticesWithoutAllocating) {
  Grid g = grid(12, 0.005);
  FclSurfaceContact fcl(g.faces, g.x);
  const Capsule c = capsule(Vec3(0.0, 0.030, 0.020), Vec3(0.060, 0.030, 0.020), 0.005);  // 20 mm above
  EXPECT_EQ(fcl.collide_capsule(c.back, c.tip, c.radius), 0);
  // lift a bump of vertices around (30, 30) mm by 18 mm: their triangles now reach the probe
  for (Vec3& p : g.x)
    if ((p.head<2>() - Eigen::Vector2d(0.030, 0.030)).norm() < 0.006) p.z() = 0.018;
  const long before = test::allocation_count();
  int hits = 0;
  for (int k = 0; k < 100; ++k) {
    fcl.refit(g.x);
    hits = fcl.collide_capsule(c.back, c.tip, c.radius);
  }
  EXPECT_EQ(test::allocation_count() - before, 0) << "refit + fcl::collide allocated";
  EXPECT_GT(hits, 0);
  for (int f : fcl.hits()) {
    bool lifted = false;
    for (int p : g.faces[f]) lifted |= g.x[p].z() > 0.01;
    EXPECT_TRUE(lifted) << "triangle " << f << " does not touch the probe";
  }
}

}  // namespace
}  // namespace ps
