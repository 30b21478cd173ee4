// Shell-model elements (Model::shells, engine/step/shell_elastic.cpp), built once at compile time
// from the closed surface triangulation of each `model: shell` component (its particles are the
// surface's vertices).
#pragma once
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

// Per-particle material of the shell model; mu = 0: the particle is not part of a shell.
struct ShellParticle {
  double mu = 0.0;         // shear modulus [Pa]
  double poisson = 0.0;    // Poisson ratio [-]
  double thickness = 0.0;  // wall thickness t [m]
};

// Signed dihedral angle of a hinge [rad]: x0, x1 the edge, x2 the opposite vertex of the face
// (x0, x1, x2), x3 that of the face (x1, x0, x3); 0 when flat, positive when the faces fold
// towards their normals' side. grad (optional, 4 entries): d theta / d x_i [1/m].
double hinge_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, Vec3* grad = nullptr);

// Fills model.shells for every component whose particles have mu > 0 (needs model.surfaces).
// Each surface face becomes a triangle, each edge shared by two faces a hinge. Throws CompileError
// naming the component when its surface has an edge with more than two faces (not a manifold) or
// a face of zero area.
void build_shell_elements(Model& model, const std::vector<ShellParticle>& material);

}  // namespace ps
