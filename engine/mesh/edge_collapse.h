// Coarsening of a closed surface by edge collapse: the simplification used where grid
// clustering cannot work (walls or features thinner than the grid cell, e.g. a hip bone at a
// 7 mm spacing), because each collapse is local and keeps the surface a closed 2-manifold of the
// same genus however thin it is.
#pragma once
#include "engine/mesh/tri_mesh.h"

namespace ps {

struct CollapseStats {
  int collapses = 0;          // edges collapsed
  int refused = 0;            // collapses refused (topology or a face turning over)
};

// Collapses edges shorter than min_edge_m, shortest first, each into its midpoint, unless the
// collapse would change the topology (link condition; a vertex left with fewer than three
// faces) or turn a face by more than ~70 degrees / make it a sliver. The input must be a closed,
// 2-manifold, consistently oriented surface (check_mesh(...).valid_solid()); the result is one
// too, with the same genus, unreferenced vertices removed. Deterministic (ties broken by vertex
// index). Throws std::invalid_argument for min_edge_m <= 0 or not finite.
TriMesh collapse_short_edges(const TriMesh& closed_surface, double min_edge_m, CollapseStats* stats = nullptr);

}  // namespace ps
