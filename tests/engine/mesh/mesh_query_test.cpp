// MeshQuery against analytic answers for a sphere and a cube, plus the speed the simulator needs
// (10k+ triangles, 100k queries well under a second).
#include "engine/mesh/mesh_query.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "engine/mesh/mesh_check.h"
#include "engine/mesh/mesh_import.h"
#include "tests/engine/mesh/query_points.h"

namespace ps {
namespace {

// Icosphere of radius r [m]: 20 * 4^levels outward triangles, vertices on the sphere.
TriMesh icosphere(double r, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriMesh m;
  for (const auto& v : {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0), Vec3(0, -1, t),
                        Vec3(0, 1, t), Vec3(0, -1, -t), Vec3(0, 1, -t), Vec3(t, 0, -1), Vec3(t, 0, 1),
                        Vec3(-t, 0, -1), Vec3(-t, 0, 1)})
    m.vertices.push_back(v.normalized());
  m.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return mid[key] = static_cast<int>(m.vertices.size()) - 1;
    };
    std::vector<std::array<int, 3>> faces;
    for (const auto& f : m.faces) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      faces.push_back({f[0], a, c});
      faces.push_back({f[1], b, a});
      faces.push_back({f[2], c, b});
      faces.push_back({a, b, c});
    }
    m.faces = std::move(faces);
  }
  for (Vec3& v : m.vertices) v *= r;
  return m;
}

// Largest gap between the polyhedron and the sphere (face planes lie inside the sphere).
double sagitta(const TriMesh& m, double r) {
  double min_plane = r;
  for (const auto& f : m.faces) {
    const Vec3 n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]).normalized();
    min_plane = std::min(min_plane, n.dot(m.vertices[f[0]]));
  }
  return r - min_plane;
}

TEST(MeshQuery, SphereInsideAndDistanceMatchAnalytic) {
  const double R = 0.02;   // 2 cm
  const TriMesh s = icosphere(R, 4);
  ASSERT_TRUE(check_mesh(s).valid_solid());
  const double h = sagitta(s, R);
  EXPECT_LT(h, 1e-4 * 2);   // 5120 triangles: within 0.2 mm of the true sphere
  const MeshQuery q(s);
  EXPECT_EQ(q.num_faces(), 5120);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2 * R, 2 * R);
  int checked_inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double r = p.norm();
    const double d = q.distance(p);
    // The polyhedron lies between radius R - h and R.
    // Between the two spheres the point may lie on either side of the polyhedron.
    const double lo = r >= R ? r - R : std::max(0.0, (R - h) - r);
    const double hi = r >= R ? r - (R - h) : r > R - h ? h : R - r;
    EXPECT_GE(d, lo - 1e-12) << "p = " << p.transpose();
    EXPECT_LE(d, hi + 1e-12) << "p = " << p.transpose();
    const Vec3 c = q.closest_point(p);
    EXPECT_NEAR((c - p).norm(), d, 1e-12);
    EXPECT_GE(c.norm(), R - h - 1e-12);
    EXPECT_LE(c.norm(), R + 1e-12);
    if (std::abs(r - R) > h) {
      EXPECT_EQ(q.inside(p), r < R) << "p = " << p.transpose();
      EXPECT_EQ(q.signed_distance(p) < 0, r < R);
      ++checked_inside;
    }
  }
  EXPECT_GT(checked_inside, 19000);
  EXPECT_TRUE(q.inside(Vec3::Zero()));
  EXPECT_NEAR(q.distance(Vec3::Zero()), R - h, 1e-6);
}

TEST(MeshQuery, RayHitsSphereAtItsRadius) {
  const double R = 0.03;
  const TriMesh s = icosphere(R, 4);
  const double h = sagitta(s, R);
  const MeshQuery q(s);
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0, 1);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 dir(n(rng), n(rng), n(rng));
    // From the centre: hits the shell; dir need not be unit length.
    const auto t = q.ray_hit(Vec3::Zero(), 3.7 * dir);
    ASSERT_TRUE(t.has_value());
    EXPECT_GE(*t, R - h - 1e-12);
    EXPECT_LE(*t, R + 1e-12);
    // From outside pointing away: miss. Pointing at the centre: hits the near side.
    const Vec3 o = 2 * R * dir.normalized();
    EXPECT_FALSE(q.ray_hit(o, dir).has_value());
    const auto back = q.ray_hit(o, -dir);
    ASSERT_TRUE(back.has_value());
    EXPECT_GE(*back, R - 1e-12);
    EXPECT_LE(*back, R + h + 1e-12);
  }
  EXPECT_FALSE(q.ray_hit(Vec3::Zero(), Vec3::Zero()).has_value());
}

TEST(MeshQuery, CubeGridPointsAndEdgesAreClassified) {
  // Points on the cube's symmetry planes and diagonals put naive axis rays exactly through edges
  // and vertices; the skew directions must still classify them.
  TriMesh c;
  for (int i = 0; i < 8; ++i) c.vertices.push_back(Vec3(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0));
  c.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
             {2, 6, 7}, {2, 7, 3}, {1, 3, 7}, {1, 7, 5}, {0, 4, 6}, {0, 6, 2}};
  const MeshQuery q(c);
  for (int i = -2; i <= 12; ++i)
    for (int j = -2; j <= 12; ++j)
      for (int k = -2; k <= 12; ++k) {
        const Vec3 p(i / 10.0, j / 10.0, k / 10.0);
        const bool on_surface = (p.array() >= 0).all() && (p.array() <= 1).all() &&
                                ((p.array() == 0).any() || (p.array() == 1).any());
        if (on_surface) continue;
        const bool expected = (p.array() > 0).all() && (p.array() < 1).all();
        EXPECT_EQ(q.inside(p), expected) << p.transpose();
        const Vec3 out = (p - p.cwiseMax(Vec3::Zero()).cwiseMin(Vec3::Ones()));
        const double analytic = expected ? std::min({p.x(), p.y(), p.z(), 1 - p.x(), 1 - p.y(), 1 - p.z()})
                                         : out.norm();
        EXPECT_NEAR(q.distance(p), analytic, 1e-12) << p.transpose();
      }
  const auto t = q.ray_hit(Vec3(0.5, 0.5, -1), Vec3(0, 0, 1));
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 1.0, 1e-12);
  EXPECT_NEAR(*q.ray_hit(Vec3(0.5, 0.5, 0.5), Vec3(1, 0, 0)), 0.5, 1e-12);
}

TEST(MeshQuery, RejectsBadMeshes) {
  EXPECT_THROW(MeshQuery(TriMesh{}), std::invalid_argument);
  TriMesh t;
  t.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  t.faces = {{0, 1, 3}};
  EXPECT_THROW(MeshQuery{t}, std::invalid_argument);
  t.faces = {{0, 1, 2}};
  t.vertices[1].x() = NAN;
  EXPECT_THROW(MeshQuery{t}, std::invalid_argument);
}

// 100k inside() and 100k distance() calls at points spread uniformly over 1.5x the bounding box:
// how many are inside, and every distance finite and not negative. (Their speed is a benchmark,
// not a test: `prostatesim_bench --benchmark_filter=BM_MeshQuery`, bench/mesh_query_bench.cpp.)
int count_inside(const TriMesh& m) {
  const MeshQuery q(m);
  int inside = 0, bad = 0;
  for (const Vec3& p : test::query_points(m)) {
    inside += q.inside(p);
    const double d = q.distance(p);
    bad += !(std::isfinite(d) && d >= 0.0);
  }
  EXPECT_EQ(bad, 0);
  return inside;
}

TEST(MeshQuery, HundredThousandQueriesOverASphereAndThePhantom) {
  const double R = 0.025;
  // Fraction of the cube [-1.5R, 1.5R]^3 inside the sphere: (4/3 pi) / 27 = 0.155.
  EXPECT_NEAR(count_inside(icosphere(R, 5)) / 1e5, 4.0 / 3.0 * std::acos(-1.0) / 27.0, 0.01);  // 20480 triangles
  MeshImportOptions opt;
  opt.units = "mm";
  const TriMesh phantom = import_mesh(std::string(PROSTATESIM_SHARED_DATA) + "/prostate_phantom/prostate.stl", opt);
  const int inside = count_inside(phantom);  // 8084 triangles, an organ-like shape in its box
  EXPECT_GT(inside, 0);
  EXPECT_LT(inside, 100000);
}

}  // namespace
}  // namespace ps
