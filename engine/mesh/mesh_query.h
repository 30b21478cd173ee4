// Spatial queries against a fixed triangle surface: point containment, distance / closest point
// and ray casting, accelerated by a bounding-volume hierarchy over the triangles built once.
// All query methods are const and keep no scratch state, so one MeshQuery may be shared by
// several threads.
#pragma once
#include <optional>
#include <vector>

#include "engine/mesh/tri_mesh.h"
#include "engine/util/vec.h"

namespace ps {

class MeshQuery {
 public:
  // The surface should be closed and outward-oriented for inside() (see repair_closed_surface);
  // distance and ray queries work on any surface. Throws std::invalid_argument for an empty
  // mesh, an index out of range or a non-finite vertex.
  explicit MeshQuery(const TriMesh& surface);

  struct Closest {
    Vec3 point;        // closest point on the surface [m]
    double distance;   // [m]
    int face;          // index into the input faces
  };
  Closest closest(const Vec3& p) const;
  Vec3 closest_point(const Vec3& p) const { return closest(p).point; }
  double distance(const Vec3& p) const { return closest(p).distance; }   // unsigned [m]

  // Containment by ray parity, voted over up to three skew directions so that a ray grazing an
  // edge or vertex cannot flip the answer. Points on the surface may go either way.
  bool inside(const Vec3& p) const;
  // Negative inside, positive outside [m].
  double signed_distance(const Vec3& p) const;

  // Distance [m] along dir (need not be unit length) from origin to the first surface hit at or
  // beyond origin; nullopt when the ray misses or dir is zero.
  std::optional<double> ray_hit(const Vec3& origin, const Vec3& dir) const;

  int num_faces() const { return static_cast<int>(tris_.size()); }

 private:
  struct Tri {
    Vec3 a, b, c;   // [m]
    int face;
  };
  struct Plane {
    Vec3 n;     // unit normal (zero for a degenerate triangle)
    double d;   // n . a [m]
  };
  // A BVH node holds the boxes of both children (64 bytes, one cache line), so that one load
  // decides where to descend. Boxes are floats rounded outward: conservative, half the memory.
  struct Node {
    float lo[2][3], hi[2][3];   // child boxes [m]
    int index[2];               // inner child: node index; leaf child: first triangle in tris_
    int count[2];               // leaf child: number of triangles; inner child: 0; none: -1
  };
  struct Child {
    int index, count;
    Vec3 lo, hi;
  };
  Child build(int first, int count, std::vector<Vec3>& centroids);
  static void store_box(Node& n, int k, const Vec3& lo, const Vec3& hi);
  int crossings(const Vec3& p, const Vec3& dir) const;

  std::vector<Tri> tris_;       // in BVH leaf order
  std::vector<Plane> planes_;   // same order: cheap lower bound for distance queries
  std::vector<Node> nodes_;     // nodes_[0] is the root
  Vec3 lo_, hi_;                // bounding box of the whole surface [m]
};

}  // namespace ps
