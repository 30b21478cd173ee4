#include "render/primitives.h"

#include <cmath>

namespace ps::render {

namespace {
constexpr double kPi = 3.14159265358979323846;
void vert(PrimitiveMesh& m, double x, double y, double z, double nx, double ny, double nz) {
  for (double v : {x, y, z, nx, ny, nz}) m.vertices.push_back(static_cast<float>(v));
}
uint32_t count(const PrimitiveMesh& m) { return static_cast<uint32_t>(m.vertices.size() / 6); }
}  // namespace

PrimitiveMesh unit_sphere(int slices, int stacks) {
  PrimitiveMesh m;
  for (int i = 0; i <= stacks; ++i) {
    const double th = kPi * i / stacks;
    for (int j = 0; j <= slices; ++j) {
      const double ph = 2 * kPi * j / slices;
      const double x = std::sin(th) * std::cos(ph), y = std::sin(th) * std::sin(ph), z = std::cos(th);
      vert(m, x, y, z, x, y, z);
    }
  }
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const uint32_t a = i * (slices + 1) + j, b = a + slices + 1;
      m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  return m;
}

PrimitiveMesh unit_cylinder(int slices) {
  PrimitiveMesh m;
  for (int j = 0; j <= slices; ++j) {
    const double ph = 2 * kPi * j / slices, c = std::cos(ph), s = std::sin(ph);
    vert(m, c, s, 0, c, s, 0);
    vert(m, c, s, 1, c, s, 0);
  }
  for (int j = 0; j < slices; ++j) {
    const uint32_t a = 2 * j, b = a + 2;
    m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
  }
  // end caps (outward normals -z and +z): the mesh is closed, so the renderer may cull back faces
  for (int end = 0; end < 2; ++end) {
    const double z = end, nz = end ? 1.0 : -1.0;
    const uint32_t centre = count(m);
    vert(m, 0, 0, z, 0, 0, nz);
    for (int j = 0; j <= slices; ++j) {
      const double ph = 2 * kPi * j / slices;
      vert(m, std::cos(ph), std::sin(ph), z, 0, 0, nz);
    }
    for (int j = 0; j < slices; ++j) {
      if (end) m.indices.insert(m.indices.end(), {centre, centre + 1 + j, centre + 2 + j});
      else m.indices.insert(m.indices.end(), {centre, centre + 2 + j, centre + 1 + j});
    }
  }
  return m;
}

PrimitiveMesh unit_cone(int slices) {
  PrimitiveMesh m;
  const double k = 1.0 / std::sqrt(2.0);
  for (int j = 0; j <= slices; ++j) {
    const double ph = 2 * kPi * j / slices, c = std::cos(ph), s = std::sin(ph);
    vert(m, c, s, 0, c * k, s * k, k);
    vert(m, 0, 0, 1, c * k, s * k, k);
  }
  for (int j = 0; j < slices; ++j) {
    const uint32_t a = 2 * j, b = a + 2;
    m.indices.insert(m.indices.end(), {a, b, a + 1});
  }
  const uint32_t centre = count(m);
  vert(m, 0, 0, 0, 0, 0, -1);
  for (int j = 0; j <= slices; ++j) {
    const double ph = 2 * kPi * j / slices;
    vert(m, std::cos(ph), std::sin(ph), 0, 0, 0, -1);
  }
  for (int j = 0; j < slices; ++j) m.indices.insert(m.indices.end(), {centre, centre + 2 + j, centre + 1 + j});
  return m;
}

}  // namespace ps::render
