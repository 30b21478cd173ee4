// A triangle surface: vertex positions and faces (counter-clockwise seen from outside for a
// closed, outward-oriented surface). Used for imported organ meshes, generated primitives,
// component surfaces and OBJ output.
#pragma once
#include <array>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

struct TriMesh {
  std::vector<Vec3> vertices;               // [nv] positions [m]
  std::vector<std::array<int, 3>> faces;    // [nf] vertex indices, outward CCW
};

// Signed volume enclosed by a closed, consistently oriented surface [m^3]
// (positive when outward-oriented).
double signed_volume(const TriMesh& mesh);

}  // namespace ps
