// Unit meshes the instruments are drawn from (instanced): sphere of radius 1, cylinder and cone
// of radius 1 from z = 0 to z = 1. Vertices interleave position and normal (6 floats).
#pragma once
#include <cstdint>
#include <vector>

namespace ps::render {

struct PrimitiveMesh {
  std::vector<float> vertices;     // x y z nx ny nz
  std::vector<uint32_t> indices;   // CCW outward
};

PrimitiveMesh unit_sphere(int slices, int stacks);
PrimitiveMesh unit_cylinder(int slices);   // side and both end caps (closed, outward wound: back faces may be culled)
PrimitiveMesh unit_cone(int slices);       // side and base

}  // namespace ps::render
