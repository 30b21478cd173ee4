// Tet-model elements (Model::tets, engine/step/tet_elastic.cpp), built once at compile time from
// the rest positions: a Delaunay tetrahedralisation of each tet-model component's particles,
// trimmed to the component's closed surface, plus elements across linked interfaces.
#pragma once
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

// An element whose volume is below this fraction of its mean edge length cubed is a sliver (a
// regular tetrahedron has 0.118, the six of a lattice cube 0.076): its stiffness per mass would
// set a tiny stable substep for no accuracy, so it is left out (counted in the warnings).
inline constexpr double kTetSliverQuality = 0.01;
// An element with an edge longer than this many spacings bridges a hole or a concavity (the
// Delaunay hull of a non-convex set) and is left out; a lattice cube's diagonal is 1.73.
inline constexpr double kTetMaxEdgeSpacings = 2.6;

// Per-particle material of the tet model; mu = 0: the particle is not part of a tet component.
struct TetParticle {
  double mu = 0.0;      // shear modulus [Pa]
  double lambda = 0.0;  // Lamé lambda [Pa]
  bool implicit_pressure = false;  // its node's volumetric term is the implicit constraint (Model::tet_pressure)
};

// A pair of components whose interface gets elements spanning it (links: between two tet-model
// components): particles of a and b closer than `distance` to the other component.
struct TetLink {
  int a = -1, b = -1;
  double distance = 0.0;  // [m]
};

// Fills model.tets for every component whose particles have mu > 0 (needs model.surfaces and
// model.components[].spacing). `excluded[c]` lists surfaces whose inside component c must not
// fill (fat around organs). Returns warnings (slivers or hull elements dropped, particles left
// without an element). Throws CompileError naming the component when it gets no element.
std::vector<std::string> build_tet_elements(Model& model, const std::vector<TetParticle>& material,
                                            const std::vector<std::vector<int>>& excluded,
                                            const std::vector<TetLink>& links);

// Fills te.g4 from te.g and the node -> element lists (TetElements::g4, gather_*). Call after the
// last change to te.g, v, their order or fast_count.
void pack_tet_blocks(TetElements& te);

// Generalised winding number of a closed surface (faces index `pos`) about point q: 1 inside,
// 0 outside (van Oosterom & Strackee solid angles).
double winding_number(const std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& pos, const Vec3& q);

}  // namespace ps
