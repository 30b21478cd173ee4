// Row kernel of the speckle source (speckle.h): the complex lattice noise at n rest points (in
// lattice units) times their backscatter amplitude. Branch-free over the row so the compiler
// vectorises it; built for AVX2 and the baseline (target_clones, chosen at load time): integer
// hashing and IEEE float arithmetic without FMA give bit-identical results on both.
#pragma once

namespace ps::us {

void speckle_row(const float* qx, const float* qy, const float* qz, const float* amp, float* re, float* im, int n);

}  // namespace ps::us
