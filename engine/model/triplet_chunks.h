// The chunk layout of the beta triplets (Model::chunks, see TripletChunk in model.h), derived once
// from Model::beta and the neighbour lists. The shape-memory stage (engine/step/shape_memory.cpp)
// reads only this layout, so every Model that is stepped has it: compute_discrete_coordinates
// builds it.
#pragma once
#include "engine/model/discrete_coordinates.h"
#include "engine/model/model.h"

namespace ps {

// Slots the stage's per-particle arrays hold: every neighbour, the padding slot after the last
// one (a half-chunk reads slots c and c + 1), and room to clear them in whole vectors of 4.
inline constexpr int kChunkSlots = kMaxNeighbours + 4;

// Fills model.chunk_start, chunks, chunk_beta and most_chunks from model.beta, beta_start,
// nbr_start and nbr. Triplets are paired greedily into half-chunks: two triplets whose vertices,
// after a cyclic rotation of each (the same normal n = (x_b - x_a) x (x_c - x_a)), read
// (a, b, c) and (a, b, c + 1); a triplet left over gets a lane with b = 0. Throws CompileError
// naming the particle if a triplet's vertex is not among its neighbours.
void build_triplet_chunks(Model& model);

}  // namespace ps
