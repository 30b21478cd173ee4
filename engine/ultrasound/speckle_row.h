// Row kernel of the speckle source (speckle.h): the complex lattice noise at n rest points (in
// lattice units, trilinear between the hashed lattice values) times their backscatter amplitude. Branch-free over the row so the compiler
// vectorises it; built for AVX2 and the baseline (target_clones, chosen at load time): integer
// hashing and IEEE float arithmetic without FMA give bit-identical results on both.
#pragma once
#include <cstddef>

namespace ps::us {

// add: accumulate into re, im (the imager sums two lattices) instead of overwriting them
// Lattice coordinates of n rest points (X0, X1, X2 [m]) for the two lattices: R1 X / step and
// R2 X / step + 1/2 (3 x 3 rotations, row-major), into rows q, q + stride, ... q + 5 stride.
void lattice_row(const float* X0, const float* X1, const float* X2, const float* R1, const float* R2, float inv_step,
                 float* q, size_t stride, int n);

// texture_noise() (speckle.h) of n rest points X / scale (X0, X1, X2 [m], inv_scale [1/m]) into out,
// the same values, vectorised.
void texture_row(const float* X0, const float* X1, const float* X2, float inv_scale, float* out, int n);

void speckle_row(const float* qx, const float* qy, const float* qz, const float* amp, float* re, float* im, int n, bool add);

}  // namespace ps::us
