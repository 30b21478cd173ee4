// Closed, outward-oriented, 2-manifold triangle surfaces built from parameters (no file input):
// the primitives the default anatomy is made of. Pure geometry, deterministic: the same
// arguments give the same vertices and faces, in the same order, on every run.
#pragma once
#include <functional>
#include <vector>

#include "engine/mesh/tri_mesh.h"
#include "engine/util/vec.h"

namespace ps::anatomy {

// Unit sphere from an icosahedron whose faces are split in four `levels` times
// (10 * 4^levels + 2 vertices; level 3: 642 vertices, 1280 faces). Edges stay within ~20 % of
// each other, which keeps the later remesh and the particle fill even.
TriMesh icosphere(int levels);

// Maps every vertex of a unit sphere through `map` (unit direction -> point [m]). The result is
// an embedded surface when `map` sends the sphere injectively onto a star-shaped surface, e.g.
// an ellipsoid with direction-dependent semi-axes; faces keep their order and orientation.
TriMesh map_sphere(const TriMesh& unit_sphere, const std::function<Vec3(const Vec3&)>& map);

// Tube of radius `radius` [m] swept along the polyline `path` [m] (at least 2 points), closed by
// hemispherical caps: `ring` vertices per cross-section, `cap_rings` rings per cap. Cross-section
// frames are parallel-transported along the path (no twist). The path's radius of curvature
// must exceed `radius` (checked by the caller with check_mesh, not here).
TriMesh swept_tube(const std::vector<Vec3>& path, double radius, int ring, int cap_rings);

// Axis-aligned box [lo, hi] with every face split into a regular grid of about `edge` [m]
// (two triangles per cell), outward-oriented.
TriMesh grid_box(const Vec3& lo, const Vec3& hi, double edge);

// Points along a polyline resampled at about `step` [m] (end points kept).
std::vector<Vec3> resample_polyline(const std::vector<Vec3>& path, double step);

}  // namespace ps::anatomy
