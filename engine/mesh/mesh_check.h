// Topology and geometry checks of a triangle surface, and the one safe repair for surfaces that
// are meant to be closed (organ and obstacle surfaces): weld, drop collapsed faces, orient
// outward. Anything that would need guessing (holes, non-manifold edges, slivers) is refused.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "engine/mesh/tri_mesh.h"

namespace ps {

struct MeshReport {
  int vertices = 0;
  int faces = 0;
  int invalid_faces = 0;            // faces with a vertex index out of range (ignored below)
  int non_finite_vertices = 0;      // NaN/Inf coordinates
  int unreferenced_vertices = 0;
  int boundary_edges = 0;           // edges of exactly one face: holes
  int non_manifold_edges = 0;       // edges of more than two faces
  int non_manifold_vertices = 0;    // vertices whose faces form several fans (bow ties)
  int degenerate_faces = 0;         // repeated vertex index, or area < tolerance
  int inconsistent_edges = 0;       // two-face edges walked in the same direction by both faces
  int components = 0;               // connected through shared vertices
  double area = 0.0;                // [m^2]
  double signed_volume = 0.0;       // [m^3]; only meaningful when closed() and consistent
  bool inverted = false;            // closed, consistent, and signed volume < 0 (inside out)

  // First offender of each kind (vertex indices / face index), -1 when there is none.
  std::array<int, 2> first_boundary_edge{-1, -1};
  std::array<int, 2> first_non_manifold_edge{-1, -1};
  std::array<int, 2> first_inconsistent_edge{-1, -1};
  int first_non_manifold_vertex = -1;
  int first_degenerate_face = -1;
  int first_invalid_face = -1;

  // Every edge has exactly two faces (and all indices are valid).
  bool closed() const { return invalid_faces == 0 && boundary_edges == 0 && non_manifold_edges == 0; }
  // A closed, 2-manifold, consistently oriented surface without degenerate faces whose total
  // signed volume is positive (outward; a single inward component among several is not seen).
  bool valid_solid() const {
    return closed() && non_finite_vertices == 0 && non_manifold_vertices == 0 &&
           degenerate_faces == 0 && inconsistent_edges == 0 && !inverted;
  }
  // One line listing every problem found (or "closed 2-manifold ...").
  std::string summary() const;
};

// Degenerate-face tolerance: area below this times the squared bounding-box diagonal.
inline constexpr double kDegenerateAreaRel = 1e-12;

MeshReport check_mesh(const TriMesh& mesh, double degenerate_area_rel = kDegenerateAreaRel);

struct RepairStats {
  int merged_vertices = 0;    // vertices welded onto another within the tolerance
  int dropped_faces = 0;      // collapsed (repeated vertex) or cancelling duplicate faces
  int flipped_faces = 0;      // faces reversed to make the orientation consistent and outward
};

// Removes faces with a repeated vertex index, and resolves faces over the same three vertices
// so that their edges keep two faces where the rest of the surface allows it: one face is kept
// (oriented against its neighbours) where each edge has one face outside the group, none where
// each has two or none; other groups are left alone. kept_from, if given, receives the input
// index of each remaining face. Indices must be valid. Returns the number of faces removed.
int remove_collapsed_and_duplicate_faces(TriMesh& mesh, std::vector<int>* kept_from = nullptr);

// Vertex welding tolerance relative to the bounding-box diagonal.
inline constexpr double kWeldRel = 1e-6;

// Repairs what is safe and refuses the rest with InputError(file_for_errors, ...):
//  - welds vertices closer than kWeldRel * bbox diagonal,
//  - drops faces that collapsed to a repeated vertex and surplus faces over the same three
//    vertices (remove_collapsed_and_duplicate_faces),
//  - orients every connected component consistently and outward (positive own volume;
//    nested shells such as cavities are therefore not supported),
//  - removes unreferenced vertices.
// Refused: non-finite coordinates, bad indices, holes ("open surface: N boundary edges, first
// at vertices a-b"), non-manifold edges, non-orientable surfaces and remaining zero-area faces
// (named by their index in the input mesh). Bow-tie vertices (two fans meeting at one vertex)
// are kept: inside tests and volumes are still right; check_mesh reports them.
TriMesh repair_closed_surface(TriMesh mesh, const std::string& file_for_errors,
                              RepairStats* stats = nullptr);

}  // namespace ps
