// 100k points spread uniformly over 1.5x a mesh's bounding box (seeded: the same points every
// run), shared by the MeshQuery test (tests/engine/mesh/mesh_query_test.cpp: what the queries
// answer) and its benchmark (bench/mesh_query_bench.cpp: how fast).
#pragma once
#include <random>
#include <vector>

#include "engine/mesh/tri_mesh.h"

namespace ps::test {

inline std::vector<Vec3> query_points(const TriMesh& m, int count = 100000) {
  Vec3 lo = m.vertices[0], hi = lo;
  for (const Vec3& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.75, 0.75);
  std::vector<Vec3> pts(count);
  for (Vec3& p : pts) p = 0.5 * (lo + hi) + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
  return pts;
}

}  // namespace ps::test
