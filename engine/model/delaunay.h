// Delaunay tetrahedralisation of a point set (CGAL, exact predicates), isolated in its own
// translation unit so only delaunay.cpp compiles CGAL's headers. Used at compile time by the
// tet model (engine/model/tet_elements.cpp); never in the step.
#pragma once
#include <array>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

// Every finite cell of the Delaunay tetrahedralisation of `points` [m], as four indices into
// `points`, positively oriented (det[x1-x0, x2-x0, x3-x0] > 0). Degenerate inputs (the
// co-spherical points of a lattice) are resolved by CGAL's symbolic perturbation, so no cell is
// flat; the order of the cells is deterministic for a given input. Fewer than 4 points, or all
// coplanar: no cell.
std::vector<std::array<int, 4>> delaunay_tetrahedra(const std::vector<Vec3>& points);

}  // namespace ps
