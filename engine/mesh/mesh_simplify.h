// Resampling of closed surfaces to a target edge length: vertex clustering on a grid for
// coarsening, midpoint edge splits for refining.
#pragma once
#include "engine/mesh/tri_mesh.h"

namespace ps {

inline constexpr long long kMaxSubdivideFaces = 20'000'000;
// Edge-collapse fallback: edges shorter than this times the spacing are collapsed, which leaves
// a mean edge of about the spacing (measured on the hip bone of ../shared/data at 5-12 mm).
inline constexpr double kCollapseEdgePerSpacing = 0.67;

// Splits every edge longer than max_edge_m at its midpoint (conforming: both faces of an edge
// share the midpoint) until no edge is longer. The surface geometry, volume, closedness and
// orientation are unchanged. Throws std::invalid_argument for max_edge_m <= 0, a non-finite
// value, or a result above kMaxSubdivideFaces.
TriMesh subdivide_to_spacing(const TriMesh& mesh, double max_edge_m);

struct RemeshStats {
  double cell_m = 0.0;        // grid cell that produced the result [m]
  int attempts = 0;           // clusterings tried (1 = the first was manifold)
  bool collapsed = false;     // no clustering was manifold: result from edge collapse instead
  bool fell_back = false;     // neither worked: result is the (subdivided) input
  double mean_edge_m = 0.0;   // mean edge length of the result [m]
};

// A closed, 2-manifold, outward-oriented surface approximating the input with edges of about
// spacing_m (mean edge within ~10 %). Method: subdivide so every grid cell the surface crosses
// holds vertices; cluster the vertices on a grid of spacing_m (one vertex per cell, placed by
// minimising the squared distance to the planes of its faces); drop collapsed and cancelling
// faces; require a valid solid of the input's genus; relax the vertices tangentially on the
// input surface (even edge lengths); offset along the normals to restore the input volume;
// reject if any face is folded against the input. A failed attempt is retried with shifted and
// then finer grids (down to half the spacing). Components smaller than a cell vanish. If no
// attempt works (features thinner than the spacing, e.g. a thin bone wall), the input refined to
// spacing_m is coarsened by edge collapse (collapse_short_edges, edges shorter than
// kCollapseEdgePerSpacing x spacing_m, retried with 15 % shorter edges while the result
// folds against the input, down to half the refined input's mean edge; then relaxed and volume-restored as above when that stays
// valid) and stats->collapsed is set: the result may then be denser than asked for (its mean
// edge is in stats). If no collapse is a valid solid of the input's genus without folds, the
// refined input is returned and stats->fell_back is set. The input must be a valid solid
// (check_mesh(...).valid_solid()); otherwise std::invalid_argument with the check summary.
TriMesh remesh_to_spacing(const TriMesh& closed_surface, double spacing_m,
                          RemeshStats* stats = nullptr);

}  // namespace ps
