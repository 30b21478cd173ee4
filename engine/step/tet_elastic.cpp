// Elastic force of the tet model (material `model: tet`, docs/model.md "Tet model"): linear
// tetrahedra over a Delaunay tetrahedralisation of the particles (Model::tets), with
//   E = sum_t V0_t mu_t [ 1/2 (|F_t|^2 - 3) - (J_t - 1) ]          shear, per element
//     + sum_n 1/2 kappa_n V0_n (J_n - 1)^2                           volume, per node
// F_t = sum_i (x_i - x_0) g_i^T the element's deformation gradient, J_t = det F_t, and
// J_n = V_n / V0_n the volume ratio of node n's share (a quarter of each element around it).
// The shear term is the deviatoric part of the "stable neo-Hookean" energy (Smith, de Goes, Kim
// 2018): stress-free at rest, invariant under rotation, polynomial (finite for inverted or
// collapsed elements, no log J), and with kappa = lambda + mu it linearises to Hooke's law
// mu |eps|^2 + lambda/2 (tr eps)^2. Volume is measured per node, not per element (the averaged
// nodal pressure of Bonet & Burton 1998): per-element J with a large kappa locks linear tets
// (every tet has to keep its own volume), the nodal average does not.
// Gradient: dE/dx_i = V0_t P_t g_i for the element's own vertices (g_0 = -g_1 - g_2 - g_3), with
//   P_t = mu_t (F - cof F) + pbar_t cof F,   pbar_t = mean over t's 4 nodes of kappa_n (J_n - 1)
// because dV_t/dx_i = V0_t cof(F_t) g_i and dJ_n/dx_i = sum_{t around n} dV_t/dx_i / (4 V0_n).
// A node whose material has `pressure: implicit` keeps its volume term in the energy but not in
// this force (TetElements::node_kappa_explicit is 0 for it): engine/step/tet_pressure.cpp solves it.
// Three passes: node volumes, node pressures, element forces (multi-rate: TetPass in stages.h). Forces sum to zero per element
// (momentum) and the energy is rotation invariant (angular momentum). No allocation: the node
// scratch is State::tet_node_vol, sized at make_state.
#include <algorithm>

#include "engine/step/stages.h"
#include "engine/step/simd_lanes.h"
#include "engine/step/tet_edges4.h"
#include "engine/util/multiversion.h"

namespace ps {

namespace {

// Multi-rate: the fraction of the gap between the slow force and its held part closed per tick
// (time constant 10 ticks). With the slow force kicked and the held part spread over the tick, the
// slow group's tick map (linear analysis, one mode of omega T = theta) stays stable up to
// theta = 1.975 at 2 substeps and 1.985 at 3 (the partition admits theta <= 1.8) and damps a
// mode at theta = 1 by 0.13 % per tick; at 1.0 (the whole force held each tick) it would be
// stable only to theta = 1.64 and damp 13 % per tick.
constexpr double kSlowHoldRate = 0.1;

struct ElementKinematics {
  Mat3 F;    // deformation gradient [-]
  Mat3 cof;  // cofactor of F = dJ/dF [-]
};

inline ElementKinematics kinematics(const TetElements& te, const std::vector<Vec3>& x, int t) {
  const int* v = &te.v[4 * t];
  const double* g = &te.g[9 * t];
  const Vec3 x0 = x[v[0]];
  const Vec3 e1 = x[v[1]] - x0, e2 = x[v[2]] - x0, e3 = x[v[3]] - x0;
  ElementKinematics k;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) k.F(r, c) = e1[r] * g[c] + e2[r] * g[3 + c] + e3[r] * g[6 + c];
  k.cof.col(0) = k.F.col(1).cross(k.F.col(2));
  k.cof.col(1) = k.F.col(2).cross(k.F.col(0));
  k.cof.col(2) = k.F.col(0).cross(k.F.col(1));
  return k;
}

// adds the volume share V_t/4 of elements [begin, end) to their nodes' entries of vol
// list: element indices (nullptr: [begin, end) themselves), entries [begin, end) of it
void add_volume_shares(const TetElements& te, const Vec3* x, const int* list, int begin, int end, double* vol) {
  const int* vv = te.v.data();
  const int* slot = te.node_slot.data();
  for (int k = begin; k < end; ++k) {
    const int* v = vv + 4 * (list ? list[k] : k);
    const Vec3 x0 = x[v[0]];
    const double quarter = (x[v[1]] - x0).dot((x[v[2]] - x0).cross(x[v[3]] - x0)) / 24.0;  // V_t / 4
    for (int i = 0; i < 4; ++i) vol[slot[v[i]]] += quarter;
  }
}

}  // namespace

// q[t] = V_t / 4 for the elements [begin, end) [m^3]: add_volume_shares's expression, four elements
// per vector (each lane its operations in its order: Eigen's dot is (x0 y0 + x1 y1) + x2 y2; the
// division by 24 one vector division), the rest one at a time. The same bits either way.
PS_TARGET_CLONES("arch=x86-64-v4", "avx", "default")
void tet_quarters(const int* vv, const Vec3* x, int begin, int end, double* q, double* edges, size_t stride) {
  typedef double D4 __attribute__((vector_size(32)));
  typedef double U4 __attribute__((vector_size(32), aligned(8), may_alias));
  int t = begin;
  for (; t + 4 <= end; t += 4) {
    D4 e[3][3];  // e[j][r]: edge x_{j+1} - x_0, coordinate r
    tet_edges4(x, vv + 4 * t, e);
    if (edges) {
      #pragma GCC unroll 9
      for (int j = 0; j < 3; ++j)
        #pragma GCC unroll 3
        for (int r = 0; r < 3; ++r) *reinterpret_cast<U4*>(edges + (3 * j + r) * stride + t) = e[j][r];
    }
    const D4 c0 = e[1][1] * e[2][2] - e[1][2] * e[2][1];
    const D4 c1 = e[1][2] * e[2][0] - e[1][0] * e[2][2];
    const D4 c2 = e[1][0] * e[2][1] - e[1][1] * e[2][0];
    *reinterpret_cast<U4*>(q + t) = ((e[0][0] * c0 + e[0][1] * c1) + e[0][2] * c2) / 24.0;
  }
  for (; t < end; ++t) {
    const int* v = vv + 4 * t;
    const Vec3 x0 = x[v[0]];
    q[t] = (x[v[1]] - x0).dot((x[v[2]] - x0).cross(x[v[3]] - x0)) / 24.0;
    if (edges)
      for (int j = 0; j < 3; ++j)
        for (int r = 0; r < 3; ++r) edges[(3 * j + r) * stride + t] = x[v[j + 1]][r] - x0[r];
  }
}

// The volume shares of the elements [begin, end) added to vol, gathered per node when the range is the
// fast group, the slow group or all of them (TetElements::gather_elem): each element's share into q
// (State::tet_quarter, [nt + 1] scratch, q[nt] = -0.0), then each node's sum over its elements in
// element order: the same additions in the same order as the scatter, so the same bits, but a
// node's running sum stays in a register instead of going through memory once per element (the
// scatter's adds into a shared node form a chain of stores and reloads), and four nodes' sums run
// side by side (padded with q[nt]: x + -0.0 == x). Other ranges, or no q: the scatter.
bool add_tet_range_volumes(const TetElements& te, const Vec3* x, int begin, int end, double* q, double* vol, double* edges) {
  const int nt = te.count(), nf = te.fast_count;
  const int nn = static_cast<int>(te.nodes.size());
  const bool lists = q && te.gather_ranges() == 3;
  const int which = !lists ? -1 : (begin == 0 && end == nt) ? 0 : (begin == 0 && end == nf) ? 1 : (begin == nf && end == nt) ? 2 : -1;
  if (which < 0) {
    add_volume_shares(te, x, nullptr, begin, end, vol);
    return false;
  }
  tet_quarters(te.v.data(), x, begin, end, q, edges, static_cast<size_t>(nt));
  // four nodes at a time (TetElements::gather_elem): four independent running sums
  const int* bs = te.gather_start[which].data();
  const int* ge = te.gather_elem[which].data();
  for (int b = 0, nb = (nn + 3) / 4; b < nb; ++b) {
    const int lanes = std::min(4, nn - 4 * b);
    double* v = vol + 4 * b;
    double s0 = v[0], s1 = lanes > 1 ? v[1] : 0.0, s2 = lanes > 2 ? v[2] : 0.0, s3 = lanes > 3 ? v[3] : 0.0;
    for (int j = bs[b]; j < bs[b + 1]; ++j) {
      const int* e = ge + 4 * j;
      s0 += q[e[0]];
      s1 += q[e[1]];
      s2 += q[e[2]];
      s3 += q[e[3]];
    }
    v[0] = s0;
    if (lanes > 1) v[1] = s1;
    if (lanes > 2) v[2] = s2;
    if (lanes > 3) v[3] = s3;
  }
  return edges != nullptr;
}

namespace {

inline bool add_node_volumes(const TetElements& te, const std::vector<Vec3>& x, int begin, int end, double* q, double* vol,
                             double* edges = nullptr) {
  return add_tet_range_volumes(te, x.data(), begin, end, q, vol, edges);
}

// current volume share V_n of every tet node into vol (indexed like te.nodes); q: as add_node_volumes
bool node_volumes(const TetElements& te, const std::vector<Vec3>& x, double* q, double* vol, double* edges = nullptr) {
  const int nn = static_cast<int>(te.nodes.size());
  for (int a = 0; a < nn; ++a) vol[a] = 0.0;
  return add_node_volumes(te, x, 0, te.count(), q, vol, edges);
}

// C = cof F for a scalar or a vector of lanes (the scalar pass and element_forces_block share it, so
// each lane does the scalar pass's operations): columns col0 = F.col1 x F.col2, col1 = F.col2 x
// F.col0, col2 = F.col0 x F.col1
template <class T>
__attribute__((always_inline)) inline void cofactor(const T (&F)[3][3], T (&C)[3][3]) {
  C[0][0] = F[1][1] * F[2][2] - F[2][1] * F[1][2];
  C[1][0] = F[2][1] * F[0][2] - F[0][1] * F[2][2];
  C[2][0] = F[0][1] * F[1][2] - F[1][1] * F[0][2];
  C[0][1] = F[1][2] * F[2][0] - F[2][2] * F[1][0];
  C[1][1] = F[2][2] * F[0][0] - F[0][2] * F[2][0];
  C[2][1] = F[0][2] * F[1][0] - F[1][2] * F[0][0];
  C[0][2] = F[1][0] * F[2][1] - F[2][0] * F[1][1];
  C[1][2] = F[2][0] * F[0][1] - F[0][0] * F[2][1];
  C[2][2] = F[0][0] * F[1][1] - F[1][0] * F[0][1];
}

// The element pass in plain scalars (no Eigen temporaries): F, its cofactor and
// P = V0 (mu F + (pbar - mu) cof F) stay in registers; about half the time of the Mat3 form.
// Elements [begin, end); node pressures p [Pa] (indexed like te.nodes); forces times scale added to f.
// list: element indices (nullptr: [begin, end) themselves), entries [begin, end) of it.
inline void element_forces_scalar(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end,
                                  double scale, Vec3* f) {
  const int* vv = te.v.data();
  const int* slot = te.node_slot.data();
  const double* gg = te.g.data();
  const double* vol0 = te.vol0.data();
  const double* mu_t = te.mu.data();
  for (int k = begin; k < end; ++k) {
    const int t = list ? list[k] : k;
    const int* v = vv + 4 * t;
    const double* g = gg + 9 * t;
    const double* x0 = x[v[0]].data();
    const double* x1 = x[v[1]].data();
    const double* x2 = x[v[2]].data();
    const double* x3 = x[v[3]].data();
    double e1[3], e2[3], e3[3];
    for (int r = 0; r < 3; ++r) { e1[r] = x1[r] - x0[r]; e2[r] = x2[r] - x0[r]; e3[r] = x3[r] - x0[r]; }
    double F[3][3];  // F[r][c]
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) F[r][c] = e1[r] * g[c] + e2[r] * g[3 + c] + e3[r] * g[6 + c];
    double C[3][3];
    cofactor(F, C);
    const double pbar = 0.25 * (p[slot[v[0]]] + p[slot[v[1]]] + p[slot[v[2]]] + p[slot[v[3]]]);
    const double a = scale * vol0[t] * mu_t[t], b = scale * vol0[t] * (pbar - mu_t[t]);
    double P[3][3];  // V0 x first Piola stress [N m]
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) P[r][c] = a * F[r][c] + b * C[r][c];
    double f1[3], f2[3], f3[3];
    for (int r = 0; r < 3; ++r) {
      f1[r] = -(P[r][0] * g[0] + P[r][1] * g[1] + P[r][2] * g[2]);
      f2[r] = -(P[r][0] * g[3] + P[r][1] * g[4] + P[r][2] * g[5]);
      f3[r] = -(P[r][0] * g[6] + P[r][1] * g[7] + P[r][2] * g[8]);
    }
    double* F0 = f[v[0]].data();
    double* F1 = f[v[1]].data();
    double* F2 = f[v[2]].data();
    double* F3 = f[v[3]].data();
    for (int r = 0; r < 3; ++r) {
      F1[r] += f1[r];
      F2[r] += f2[r];
      F3[r] += f3[r];
      F0[r] -= f1[r] + f2[r] + f3[r];
    }
  }
}

}  // namespace

// One block of L consecutive entries [k, k + L) of the pass (L = 4 or 8; GCC vector extensions, L
// doubles per vector). Each lane does exactly the scalar pass's operations in the same order (no
// FMA in any target: -ffp-contract=off), and the forces are added to the particles lane by lane in
// element order, so the result is bit-identical to element_forces_scalar whatever L and whatever
// instruction set: only the arithmetic is vectorised, the gathers and the scatter stay scalar.
// packed: g, V0 and mu read as vectors from the blocked copy (TetElements::g4, blocks of four: L = 8
// takes two blocks); k is then a multiple of 4. list: as element_forces_scalar.
// out = lo[0..3] (L = 4) or lo[0..3], hi[0..3] (L = 8): vector loads of four (8-byte aligned)
template <int L, class V>
__attribute__((always_inline)) inline void load_fours(V& out, const double* lo, const double* hi) {
  typedef double U4 __attribute__((vector_size(32), aligned(8), may_alias));
  if constexpr (L == 4) {
    out = *reinterpret_cast<const U4*>(lo);
  } else {
    const U4 a = *reinterpret_cast<const U4*>(lo), b = *reinterpret_cast<const U4*>(hi);
    out = __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
  }
}

template <int L>
__attribute__((always_inline)) inline void element_forces_block(const TetElements& te, const Vec3* x, const double* p, const int* list,
                                                                bool packed, int k, double scale, Vec3* f, const double* ed) {
  typedef typename LaneVector<L>::type D;
  const int* vv = te.v.data();
  const int* slot = te.node_slot.data();
  const double* gg = te.g.data();
  const double* vol0 = te.vol0.data();
  const double* mu_t = te.mu.data();
  int id[L];  // lane l's element
  #pragma GCC unroll 16
  for (int l = 0; l < L; ++l) id[l] = list ? list[k + l] : k + l;
  const int* vl[L];  // vl[l][i]: lane l's vertex i
  #pragma GCC unroll 16
  for (int l = 0; l < L; ++l) vl[l] = vv + 4 * id[l];
  D e1[3], e2[3], e3[3], g[9] = {};  // g zeroed: GCC 12 cannot see that both branches below fill it (-Wmaybe-uninitialized)
  if (ed) {  // the edges the node volumes just measured at these positions (the same subtractions)
    typedef double UL __attribute__((vector_size(8 * L), aligned(8), may_alias));
    const size_t stride = static_cast<size_t>(te.count());
    #pragma GCC unroll 16
    for (int r = 0; r < 3; ++r) {
      e1[r] = *reinterpret_cast<const UL*>(ed + r * stride + k);
      e2[r] = *reinterpret_cast<const UL*>(ed + (3 + r) * stride + k);
      e3[r] = *reinterpret_cast<const UL*>(ed + (6 + r) * stride + k);
    }
  } else {
    #pragma GCC unroll 16
    for (int r = 0; r < 3; ++r) {
      D xi[4];  // coordinate r of vertex i in each lane
      #pragma GCC unroll 16
      for (int i = 0; i < 4; ++i) lanes_of<L>(xi[i], [&](int l) { return x[vl[l][i]][r]; });
      e1[r] = xi[1] - xi[0];
      e2[r] = xi[2] - xi[0];
      e3[r] = xi[3] - xi[0];
    }
  }
  if (packed) {
    const double* gb = te.g4.data() + 9 * k;  // block k / 4 (and, for eight lanes, the next one)
    #pragma GCC unroll 16
    for (int i = 0; i < 9; ++i) load_fours<L>(g[i], gb + 4 * i, gb + 36 + 4 * i);
  } else {
    #pragma GCC unroll 16
    for (int i = 0; i < 9; ++i) lanes_of<L>(g[i], [&](int l) { return gg[9 * id[l] + i]; });
  }
  D F[3][3];
  #pragma GCC unroll 16
  for (int r = 0; r < 3; ++r)
    #pragma GCC unroll 16
    for (int c = 0; c < 3; ++c) F[r][c] = e1[r] * g[c] + e2[r] * g[3 + c] + e3[r] * g[6 + c];
  D C[3][3];
  cofactor(F, C);
  D ps, sv0, mu;
  lanes_of<L>(ps, [&](int l) {
    const int* w = vl[l];
    return p[slot[w[0]]] + p[slot[w[1]]] + p[slot[w[2]]] + p[slot[w[3]]];
  });
  if (packed) {
    load_fours<L>(sv0, vol0 + k, vol0 + k + 4);
    load_fours<L>(mu, mu_t + k, mu_t + k + 4);
  } else {
    lanes_of<L>(sv0, [&](int l) { return vol0[id[l]]; });
    lanes_of<L>(mu, [&](int l) { return mu_t[id[l]]; });
  }
  const D pbar = 0.25 * ps;
  const D sv = scale * sv0;
  const D a = sv * mu, b = sv * (pbar - mu);
  D P[3][3];
  #pragma GCC unroll 16
  for (int r = 0; r < 3; ++r)
    #pragma GCC unroll 16
    for (int c = 0; c < 3; ++c) P[r][c] = a * F[r][c] + b * C[r][c];
  D f1[3], f2[3], f3[3];
  #pragma GCC unroll 16
  for (int r = 0; r < 3; ++r) {
    f1[r] = -(P[r][0] * g[0] + P[r][1] * g[1] + P[r][2] * g[2]);
    f2[r] = -(P[r][0] * g[3] + P[r][1] * g[4] + P[r][2] * g[5]);
    f3[r] = -(P[r][0] * g[6] + P[r][1] * g[7] + P[r][2] * g[8]);
  }
  #pragma GCC unroll 16
  for (int l = 0; l < L; ++l) {
    const int* w = vl[l];
    double* F0 = f[w[0]].data();
    double* F1 = f[w[1]].data();
    double* F2 = f[w[2]].data();
    double* F3 = f[w[3]].data();
    #pragma GCC unroll 16
    for (int r = 0; r < 3; ++r) {
      F1[r] += f1[r][l];
      F2[r] += f2[r][l];
      F3[r] += f3[r][l];
      F0[r] -= f1[r][l] + f2[r][l] + f3[r][l];
    }
  }
}

// Elements [begin, end) in blocks of L lanes (L = 8: then one of four), the rest one at a time.
// Elements in index order with the blocked copy of g: the elements before the first block
// boundary go through the scalar pass (the same bits), then whole blocks.
template <int L>
__attribute__((always_inline)) inline void element_forces_lanes(const TetElements& te, const Vec3* x, const double* p, const int* list,
                                                                int begin, int end, double scale, Vec3* f, const double* ed) {
  const bool packed = !list && te.g4.size() >= 9 * static_cast<size_t>(end);
  if (list) ed = nullptr;
  int k = begin;
  if (packed && (k & 3) != 0) {
    const int head = std::min(end, (k + 3) & ~3);
    element_forces_scalar(te, x, p, nullptr, k, head, scale, f);
    k = head;
  }
  if constexpr (L == 8)
    for (; k + 8 <= end; k += 8) element_forces_block<8>(te, x, p, list, packed, k, scale, f, ed);
  for (; k + 4 <= end; k += 4) element_forces_block<4>(te, x, p, list, packed, k, scale, f, ed);
  element_forces_scalar(te, x, p, list, k, end, scale, f);
}

// The pass four elements per vector: one AVX register, two SSE2 ones in the baseline build (target
// clones, chosen at load time).
PS_TARGET_CLONES("avx", "default")
void tet_element_forces4(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end, double scale, Vec3* f,
                         const double* ed) {
  element_forces_lanes<4>(te, x, p, list, begin, end, scale, f, ed);
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(PROSTATESIM_NO_MULTIVERSION)
#define PS_ELEMENT_FORCES_8 1
// The same eight elements per vector on AVX-512 (x86-64-v4: one register of eight doubles, and 32
// registers, so F, cof F, P and g stay in them): half the arithmetic instructions of the four-lane
// pass; the same bits (each lane its operations in its order, the scatter in element order).
__attribute__((target("arch=x86-64-v4")))
void tet_element_forces8(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end, double scale, Vec3* f,
                         const double* ed) {
  element_forces_lanes<8>(te, x, p, list, begin, end, scale, f, ed);
}
#else
// no AVX-512 build (sanitizers, other compilers): the four-lane pass, the same bits
void tet_element_forces8(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end, double scale, Vec3* f,
                         const double* ed) {
  tet_element_forces4(te, x, p, list, begin, end, scale, f, ed);
}
#endif

bool tet_element_forces8_available() {
#ifdef PS_ELEMENT_FORCES_8
  static const bool wide = __builtin_cpu_supports("x86-64-v4");
  return wide;
#else
  return false;
#endif
}

// Elements [begin, end) of the vector pass (list: as element_forces_scalar): eight per vector where
// the CPU has AVX-512 (10-13 % less time per element than four, bench BM_TetElementForces), else
// four; bit-identical either way (tested against the scalar pass).
void tet_element_forces(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end, double scale,
                        Vec3* f, const double* ed) {
  if (tet_element_forces8_available()) tet_element_forces8(te, x, p, list, begin, end, scale, f, ed);
  else tet_element_forces4(te, x, p, list, begin, end, scale, f, ed);
}

namespace {

inline void element_forces(const TetElements& te, const Vec3* x, const double* p, int begin, int end, double scale, Vec3* f,
                           const double* ed = nullptr) {
  tet_element_forces(te, x, p, nullptr, begin, end, scale, f, ed);
}

// State::tet_edges where the node volumes gather (q given) and the state has it sized (make_state), else null
inline double* edge_scratch(State& s, const double* q, int nt) {
  return q && s.tet_edges.size() >= 9 * static_cast<size_t>(nt) ? s.tet_edges.data() : nullptr;
}

// The slow elements' force at the current positions into s.tet_slow_f, with their volume shares
// into s.tet_slow_vol (held for the fast elements' node pressures until the next tick's end).
void slow_force_now(const Model& m, State& s) {
  const TetElements& te = m.tets;
  const int nt = te.count(), nf = te.fast_count;
  const int nn = static_cast<int>(te.nodes.size());
  double* vs = s.tet_slow_vol.data();
  double* p = s.tet_node_vol.data();
  double* q = s.tet_quarter.size() > static_cast<size_t>(nt) ? s.tet_quarter.data() : nullptr;  // with its -0.0 slot
  double* ed = edge_scratch(s, q, nt);
  for (int a = 0; a < nn; ++a) vs[a] = 0.0;
  const bool measured = add_node_volumes(te, s.x, nf, nt, q, vs, ed);
  for (int a = 0; a < nn; ++a) p[a] = vs[a];
  add_node_volumes(te, s.x, 0, nf, q, p);
  tet_node_pressures(te, p);
  for (Vec3& f : s.tet_slow_f) f.setZero();
  element_forces(te, s.x.data(), p, nf, nt, 1.0, s.tet_slow_f.data(), measured ? ed : nullptr);
  s.tet_slow_f_valid = 1;
}

}  // namespace

void add_tet_node_volumes(const TetElements& te, const Vec3* x, const int* list, int count, double* vol) {
  add_volume_shares(te, x, list, 0, count, vol);
}

void tet_node_pressures(const TetElements& te, double* vol) {
  const int nn = static_cast<int>(te.nodes.size());
  for (int a = 0; a < nn; ++a) vol[a] = te.node_kappa_explicit[a] * (vol[a] * te.node_inv_vol0[a] - 1.0);  // [Pa]
}

void add_tet_element_forces(const TetElements& te, const Vec3* x, const double* p, const int* list, int count, Vec3* f) {
  tet_element_forces(te, x, p, list, 0, count, 1.0, f);
}

void end_tet_tick(const Model& m, State& s, double tick) {
  slow_force_now(m, s);
  const double half = 0.5 * tick;  // the closing half kick [s]
  for (int p = 0, n = m.particle_count(); p < n; ++p) {
    if (m.inv_mass[p] == 0.0) continue;
    const Vec3 dv = half * m.inv_mass[p] * (s.tet_slow_f[p] - s.tet_slow_hold[p]);
    for (int a = 0; a < 3; ++a)
      if (!(m.locked_axes[p] & (1u << a))) s.v[p][a] += dv[a];
  }
  // the held part follows the slow force (it is the same within the tick whatever it is: the
  // tick's impulse stays the symmetric split's; only how it is spread over the tick changes)
  for (size_t q = 0; q < s.tet_slow_hold.size(); ++q) s.tet_slow_hold[q] += kSlowHoldRate * (s.tet_slow_f[q] - s.tet_slow_hold[q]);
}

void add_tet_elastic_forces(const Model& m, State& s, TetPass pass, int substeps) {
  const TetElements& te = m.tets;
  const int nt = te.count(), nf = te.fast_count;
  const int nn = static_cast<int>(te.nodes.size());
  double* p = s.tet_node_vol.data();
  if (!s.asleep.empty() && pass == TetPass::All) {
    // sleeping tissue (tet_sleep.cpp): only the elements with an awake node; a node's volume is
    // the held elements' shares plus the evaluated ones'. Everything awake: the order is 0..nt-1
    // and the held shares 0, the same sums in the same order as the plain pass.
    const int na = s.tet_awake_count;
    const int* list = s.tet_order.data();
    for (int a = 0; a < nn; ++a) p[a] = s.tet_held_vol[a];
    add_tet_node_volumes(te, s.x.data(), list, na, p);
    tet_node_pressures(te, p);
    tet_element_forces(te, s.x.data(), p, list, 0, na, 1.0, s.f.data());
    return;
  }
  const bool split = te.multirate() && pass != TetPass::All;
  double* q = s.tet_quarter.size() > static_cast<size_t>(nt) ? s.tet_quarter.data() : nullptr;  // with its -0.0 slot
  // the edges of the elements whose volumes are gathered, for their force pass (tet_edges)
  double* ed = edge_scratch(s, q, nt);
  bool fast_ed = false, slow_ed = false;  // edges measured at these positions: [0, nf) / [nf, nt) or all
  if (!split) {
    fast_ed = slow_ed = node_volumes(te, s.x, q, p, ed);
  } else {
    // the slow elements' volume shares are measured with their force (the last tick's end) and
    // held: the pressure of a node between both groups mixes the held and the current shares
    if (pass == TetPass::TickStart && !s.tet_slow_f_valid) {
      slow_force_now(m, s);
      s.tet_slow_hold = s.tet_slow_f;  // a scene starting at rest is held at rest from its first tick
    }
    double* vs = s.tet_slow_vol.data();
    if (pass == TetPass::FastOnly || pass == TetPass::SlowOnly) {
      for (int a = 0; a < nn; ++a) vs[a] = 0.0;
      slow_ed = add_node_volumes(te, s.x, nf, nt, q, vs, ed);
    }
    for (int a = 0; a < nn; ++a) p[a] = vs[a];
    fast_ed = add_node_volumes(te, s.x, 0, nf, q, p, ed);
  }
  const double* fe = fast_ed ? ed : nullptr;
  const double* se = slow_ed ? ed : nullptr;
  tet_node_pressures(te, p);
  const Vec3* x = s.x.data();
  Vec3* f = s.f.data();
  switch (pass) {
    case TetPass::All: element_forces(te, x, p, 0, nt, 1.0, f, fe); return;
    case TetPass::FastOnly: element_forces(te, x, p, 0, nf, 1.0, f, fe); return;
    case TetPass::SlowOnly: element_forces(te, x, p, nf, nt, 1.0, f, se); return;
    case TetPass::Held: {
      element_forces(te, x, p, 0, nf, 1.0, f, fe);
      for (size_t q = 0; q < s.tet_slow_hold.size(); ++q) f[q] += s.tet_slow_hold[q];
      return;
    }
    case TetPass::TickStart: {
      // the impulse method in its symmetric form (r-RESPA, Tuckerman, Berne, Martyna 1992): the
      // slow force acts as two half kicks of T/2 each, one at the tick's start (here, as a
      // force of substeps/2 times F over the first substep h) and one at its end (end_tet_tick,
      // from the force at the end positions, which is carried to open the next tick). Velocity
      // Verlet at the tick for the slow group: stable for omega T < 2, second order.
      // Only the part of the slow force that differs from the held force H (State::tet_slow_hold)
      // is kicked; H acts as a steady force on every substep. Kicking all of it left a body at
      // rest moving: a particle between the groups, kicked by its slow elements against the
      // steady pull of its fast ones, kept an orbit within the tick (14 mm/s on the biopsy scene
      // after 1 s). H follows the slow force (kSlowHoldRate per tick), so at rest the kicks
      // vanish and the tick is the plain substep loop under a constant load: exactly at rest.
      element_forces(te, x, p, 0, nf, 1.0, f, fe);
      const double k = 0.5 * substeps;
      for (size_t q = 0; q < s.tet_slow_f.size(); ++q) f[q] += k * (s.tet_slow_f[q] - s.tet_slow_hold[q]) + s.tet_slow_hold[q];
      return;
    }
  }
}

double tet_elastic_energy(const Model& m, const State& s) {
  const TetElements& te = m.tets;
  std::vector<double> vol(te.nodes.size());
  node_volumes(te, s.x, nullptr, vol.data());
  double e = 0.0;
  for (int t = 0; t < te.count(); ++t) {
    const ElementKinematics k = kinematics(te, s.x, t);
    e += te.vol0[t] * te.mu[t] * (0.5 * (k.F.squaredNorm() - 3.0) - (k.F.determinant() - 1.0));
  }
  for (size_t a = 0; a < te.nodes.size(); ++a) {
    const double j = vol[a] * te.node_inv_vol0[a];
    e += 0.5 * te.node_kappa[a] / te.node_inv_vol0[a] * (j - 1.0) * (j - 1.0);
  }
  return e;
}

}  // namespace ps
