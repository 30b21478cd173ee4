// Row kernel of the speckle source (speckle.h): the complex lattice noise at n rest points (in
// lattice units, trilinear between the hashed lattice values) times their backscatter amplitude. Branch-free over the row so the compiler
// vectorises it; built for AVX2 and the baseline (target_clones, chosen at load time): integer
// hashing and IEEE float arithmetic without FMA give bit-identical results on both.
#pragma once

namespace ps::us {

// add: accumulate into re, im (the imager sums two lattices) instead of overwriting them
void speckle_row(const float* qx, const float* qy, const float* qz, const float* amp, float* re, float* im, int n, bool add);

}  // namespace ps::us
