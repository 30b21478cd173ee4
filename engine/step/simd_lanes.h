// L doubles side by side (GCC vector extensions) for the passes that run L elements at once, each
// lane the scalar pass's operations in its order (tet_elastic.cpp, shell_elastic.cpp): the vector
// and mask types of a width, and a vector built from one value per lane.
#pragma once

namespace ps {

template <int L> struct LaneVector;  // GCC ignores a dependent vector_size: one specialisation per width
template <> struct LaneVector<4> {
  typedef double type __attribute__((vector_size(32)));
  typedef long long mask __attribute__((vector_size(32)));  // a comparison's result
};
template <> struct LaneVector<8> {
  typedef double type __attribute__((vector_size(64)));
  typedef long long mask __attribute__((vector_size(64)));
};

// out = {v(0), ..., v(L - 1)} in one expression (GCC assembles it in registers; a vector filled lane
// by lane went through the stack and stalled on store forwarding)
template <int L, class V, class Fn>
__attribute__((always_inline)) inline void lanes_of(V& out, Fn v) {
  if constexpr (L == 4) out = V{v(0), v(1), v(2), v(3)};
  else out = V{v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7)};
}

}  // namespace ps
