// The three edges of four tetrahedra as 4-lane vectors (GCC vector extensions), for the SIMD
// element passes of tet_elastic.cpp and tet_pressure.cpp: the same subtractions as the scalar
// x[v1] - x[v0] etc., so each lane has the scalar form's bits.
#pragma once
#include "engine/util/vec.h"

namespace ps {

typedef double TetD4 __attribute__((vector_size(32)));

// e[k][r] = lane l's x[v[4 l + k + 1]][r] - x[v[4 l]][r]: the edges from vertex 0 of the four
// elements whose vertices are v[0..15] (lane l's vertex i is v[4 l + i]) [m]
inline __attribute__((always_inline)) void tet_edges4(const Vec3* x, const int* v, TetD4 e[3][3]) {
  #pragma GCC unroll 16
  for (int r = 0; r < 3; ++r) {
    const TetD4 x0 = {x[v[0]][r], x[v[4]][r], x[v[8]][r], x[v[12]][r]};
    #pragma GCC unroll 16
    for (int k = 0; k < 3; ++k) e[k][r] = TetD4{x[v[k + 1]][r], x[v[5 + k]][r], x[v[9 + k]][r], x[v[13 + k]][r]} - x0;
  }
}

}  // namespace ps
