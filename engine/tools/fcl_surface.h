// FCL as the collision layer between a rigid capsule (the endorectal probe) and deforming tissue
// surfaces (the rectal wall and whatever else the probe may touch): one FCL bounding-volume
// hierarchy (BVHModel<AABB>) over the surfaces' triangles, built once at rest and refitted to
// the particles' current positions, and traversed by FCL against an fcl::Capsule to find the
// triangles with a corner within the capsule (inflated by a margin by the caller). The caller
// then projects those corners exactly (engine/tools/probe/probe.cpp); FCL only finds them.
//
// No allocation after construction (it runs inside the physics step), which needed three
// choices, each measured with the counting allocator (tests/engine/tools/fcl_surface_test.cpp):
//  - FCL's traversal is driven directly (fcl::detail::initialize + fcl::detail::collide on a
//    MeshShapeCollisionTraversalNode<AABB, Capsule>: the AABB tree against the capsule's AABB,
//    with the mesh in world coordinates), not through fcl::collide: for AABB (and kDOP) trees
//    fcl::collide copies the whole BVHModel on every call (`new BVHModel<BV>(*obj1)` in
//    collision_func_matrix-inl.h, so that it could transform the vertices). Its oriented trees
//    (OBB, OBBRSS...) are queried in place but cost 10x more to refit (an eigen-decomposition per
//    merged box: measured 0.86 ms per substep against 0.10 ms with AABB in the probe scene),
//    and all but OBB fit the capsule's box through Capsule::getBoundVertices(), a std::vector.
//  - the leaf test is overridden: fcl::collide's leaf test (GJK, GST_INDEP) runs EPA on every triangle that
//    intersects, even with enable_contact off, and FCL 0.7's EPA::initialize news its vertex
//    and face stores: 2 allocations per touching triangle (28 in the refit test; libccd news its
//    support objects on every leaf). The override asks the exact capsule distance of the
//    triangle's three corners (the particles are what the probe pushes), no GJK tolerance.
//  - hits go to a vector reserved to one entry per triangle (each leaf is visited once).
// The BVH is built once by FCL (at rest) and refitted here every query: each leaf box around
// its triangle's current corners, each parent around its children (fcl_surface.cpp says why
// not FCL's own refit). The topology stays that of the rest shape: the boxes may grow looser
// as the tissue deforms, never wrong, so a query may visit extra leaves, never skip one.
#pragma once
#include <array>
#include <memory>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

class FclSurfaceContact {
 public:
  // `faces`: triangles by particle index; `x`: positions of every particle [m] (the BVH's
  // vertices are the distinct particles of the faces, taken from x).
  FclSurfaceContact(const std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& x);
  ~FclSurfaceContact();
  FclSurfaceContact(const FclSurfaceContact&) = delete;
  FclSurfaceContact& operator=(const FclSurfaceContact&) = delete;

  // Moves the BVH's vertices to x (every vertex) and refits its boxes. No allocation.
  void refit(const std::vector<Vec3>& x);
  // Triangles with a corner inside the capsule with axis segment [a, b] and radius `radius`
  // [m], as indices into faces(), found by FCL's OBB traversal. No allocation. Returns their
  // number; hits() lists them (traversal order).
  int collide_capsule(const Vec3& a, const Vec3& b, double radius);
  const std::vector<int>& hits() const { return hits_; }

  const std::vector<std::array<int, 3>>& faces() const { return faces_; }
  const std::vector<int>& vertices() const { return vertices_; }  // particle per BVH vertex

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::array<int, 3>> faces_;   // particle indices
  std::vector<int> vertices_;               // BVH vertex -> particle
  std::vector<std::array<int, 3>> local_faces_;  // triangles by BVH vertex
  std::vector<int> hits_;                   // capacity: one per face
};

}  // namespace ps
