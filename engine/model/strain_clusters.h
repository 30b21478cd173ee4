// Strain-memory clusters (Model::strain, engine/step/strain_memory.cpp), precomputed once at
// compile time from the rest positions and the neighbourhoods.
#pragma once
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

// A cluster whose rest offsets span less than this (smallest / largest eigenvalue of S) is flat
// or collinear: its affine fit is undefined and the compiler refuses it, naming the particle.
inline constexpr double kClusterConditionMin = 1e-4;

// Relative misfit of the consistency condition above which compile warns (the box lattice's
// triangulated faces leave 0.9 %: their corner weights are not in the correction's range).
inline constexpr double kClusterConsistencyWarn = 0.02;

// Per-particle material of the strain term; a particle with mu = 0 gets no cluster.
struct StrainParticle {
  double mu = 0.0;       // shear modulus [Pa]
  double lambda = 0.0;   // Lamé lambda [Pa]
  double volume = 0.0;   // volume the particle stands for [m^3]
};

// Fills model.strain: one cluster (the particle first, then its neighbours model.nbr of the same
// component) for every particle with shape memory and mu > 0, with gradient weights corrected
// for consistent integration (strain_clusters.cpp); needs model.surfaces. Returns warnings (a
// component whose clusters cannot be made consistent). Throws CompileError naming the particle and component
// when a cluster is flat or collinear.
std::vector<std::string> build_strain_clusters(Model& model, const std::vector<StrainParticle>& material);

}  // namespace ps
