// Discrete deformation coordinates (paper §3.2.3), precomputed once at compile time.
#pragma once
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

// A triplet is rejected as collinear / near-degenerate when
//   |(N_j-N_i) x (N_k-N_i)| < kTripletQualityMin * (longest edge)^2,
// i.e. when its smallest angle is below about 1.1 degrees (an equilateral triangle scores 0.87).
inline constexpr double kTripletQualityMin = 0.02;
// |beta_t| below this fraction of the neighbourhood size is round-off of an in-plane triplet;
// such triplets need no normal at run time.
inline constexpr double kBetaZeroRelative = 1e-9;
// More neighbours than this make C(n,3) triplets too costly; the compiler refuses.
inline constexpr int kMaxNeighbours = 16;
inline constexpr int kMaxCandidates = 560;  // C(16, 3): every triplet of kMaxNeighbours

// Fills model.nbr_w, model.beta_start, model.beta, model.triplet_count (and the chunk layout of
// the beta triplets, build_triplet_chunks in triplet_chunks.h) from model.rest_pos,
// model.nbr_start/nbr for every particle with model.shape_memory[p] = 1.
// Throws CompileError naming the particle (index, component) when a particle that needs shape
// memory has fewer than 3 neighbours, more than kMaxNeighbours, or no valid triplet.
void compute_discrete_coordinates(Model& model);

}  // namespace ps
