// Small closed meshes shared by the mesh tests.
#pragma once
#include "engine/mesh/tri_mesh.h"

namespace ps::test {

// Axis-aligned cube [0, size]^3 as 12 outward CCW triangles [m].
inline TriMesh cube_mesh(double size) {
  TriMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back(size * Vec3(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0));
  m.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
             {2, 6, 7}, {2, 7, 3}, {1, 3, 7}, {1, 7, 5}, {0, 4, 6}, {0, 6, 2}};
  return m;
}

}  // namespace ps::test
