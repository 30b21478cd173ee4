#include "engine/mesh/tri_mesh.h"

namespace ps {

double signed_volume(const TriMesh& mesh) {
  double v6 = 0.0;
  for (const auto& f : mesh.faces) {
    const Vec3& a = mesh.vertices[f[0]];
    const Vec3& b = mesh.vertices[f[1]];
    const Vec3& c = mesh.vertices[f[2]];
    v6 += a.dot(b.cross(c));
  }
  return v6 / 6.0;
}

}  // namespace ps
