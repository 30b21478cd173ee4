// Particles of one component before they join the Model: positions, neighbourhoods (local
// indices) and the closed outward surface over them (used for the volume constraint, rendering
// and OBJ output). Built from primitives (box, cylinder) or from a closed triangle mesh.
#pragma once
#include <array>
#include <functional>
#include <vector>

#include "engine/mesh/tri_mesh.h"

namespace ps {

struct ParticleSet {
  std::vector<Vec3> pos;                        // [n] rest positions [m]
  std::vector<std::vector<int>> nbrs;           // [n] neighbour lists (local indices)
  std::vector<std::array<int, 3>> faces;        // closed outward surface (local indices)
  std::vector<uint8_t> on_surface;              // [n]
};

// Regular lattice in [min, max] with about `h` spacing (exact per-axis spacing size/round(size/h)).
// Volumetric: every lattice point, 6-connected. Surface: boundary points only, 6-connected among
// themselves. The surface is the lattice boundary, each quad split in two triangles.
ParticleSet box_particles(const Vec3& min, const Vec3& max, double h, bool volumetric);

// Closed triangulated cylinder surface (side rings every ~h, caps of concentric rings).
TriMesh cylinder_surface(const Vec3& base, const Vec3& axis, double radius, double length, double h);

// Particles on a closed surface mesh: one per vertex, neighbours = the vertex one-ring.
ParticleSet surface_particles(const TriMesh& surface);

// Surface particles plus an interior lattice fill at spacing h: interior points are kept when
// inside(p) and distance(p) >= 0.45 h. Interior neighbours: the nearest particle in each of the
// six axis cones within 1.75 h (lattice adjacency, or a surface particle near the boundary);
// surface particles keep their one-ring and are attached to their 2 nearest interior particles.
ParticleSet volumetric_particles(const TriMesh& surface, double h, const std::function<bool(const Vec3&)>& inside,
                                 const std::function<double(const Vec3&)>& distance);

}  // namespace ps
