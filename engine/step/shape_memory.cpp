// Shape-memory force (paper §3.2.1-3.2.3). For each elastic particle p:
//   P* = sum_j w_pj x_j + sum_t b_t n_t/|n_t|,   F* = k_e (P* - x_p),
// and -w_pj F* goes to each neighbour j ("redistributed ... proportional to the linear
// coefficient"), so internal forces sum to zero. For the linear part this is exactly the
// gradient of the energy 1/2 k_e |P* - P|^2.
//
// The beta terms make P* nonlinear in the neighbours. Redistributing only by the linear
// coefficients (the paper's literal rule, Redistribution::Linear) leaves a non-conservative
// residual: a stiff cube on a fixed base then grows an oscillation at any time step (measured:
// blow-up at t = 0.037 s for k_e = 1e6 N/m with dt from 5e-7 s down to 1.25e-7 s). The default,
// Redistribution::Gradient, also hands each triplet vertex its share -(dP*/dx_q)^T F* of the
// normal's derivative: the force is then exactly -grad of sum 1/2 k_e |P* - P|^2, conserves
// linear and angular momentum, and is stable below the explicit limit.
//
// Speed (docs/performance.md): this stage is ~90% of a step. The beta triplets of a particle are
// processed in groups of N = 2 or 4, one triplet per lane of an N-double vector (GCC vector
// extension): one square root and one division per triplet instead of five long-latency
// operations, and the gradient pass reuses the edges, normal, b/|n| and 1/|n|^2 that the
// attractor pass left in State::triplet_scratch. N is 4 for models with many triplets per
// particle (mesh-based bodies), else 2, decided from the model alone. The same source is
// compiled twice, for the x86-64 baseline (SSE2) and with AVX (VEX encoding, 256-bit registers),
// and the AVX build runs where the CPU has it. Lanes only ever do IEEE +, -, *, / and sqrt,
// "avx" brings no FMA and the lane layout does not depend on the build, so both builds give
// bit-identical forces (prostatesim_bench --verify checks it). A last, partial group fills its
// unused lanes with copies of a real triplet and discards them. Force scatters keep the original
// order (triplet by triplet, j then k then i); the beta terms of P* are summed per lane (lane l
// takes triplets l, l+N, l+2N, ...) and the lane sums added as l0 + l1, or (l0 + l1) + (l2 + l3).

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/step/stages.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#if defined(__x86_64__) && defined(__GNUC__)
#define PS_AVX_DISPATCH 1
#else
#define PS_AVX_DISPATCH 0
#endif

// 32-byte vectors are only passed inside always-inlined helpers; GCC's note that their argument
// ABI changed long ago does not concern this file.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace ps {

namespace {

#define PS_INLINE [[gnu::always_inline]] inline

// N doubles (one triplet per lane), its lane mask type, and an unaligned, may-alias view for
// loads and stores to double arrays (positions, forces, scratch).
template <int N> struct Pack;
template <> struct Pack<2> {
  typedef double D __attribute__((vector_size(16)));
  typedef int64_t M __attribute__((vector_size(16)));
  typedef double U __attribute__((vector_size(16), aligned(8), may_alias));
  static constexpr M iota{0, 1};
};
template <> struct Pack<4> {
  typedef double D __attribute__((vector_size(32)));
  typedef int64_t M __attribute__((vector_size(32)));
  typedef double U __attribute__((vector_size(32), aligned(8), may_alias));
  static constexpr M iota{0, 1, 2, 3};
};

template <int N> using D = typename Pack<N>::D;
template <int N> using M = typename Pack<N>::M;
template <int N> struct V { D<N> x, y, z; };  // a 3-vector per lane

template <int N> PS_INLINE D<N> splat(double a) { return D<N>{} + a; }
template <int N> PS_INLINE D<N> load(const double* p) { return *reinterpret_cast<const typename Pack<N>::U*>(p); }
template <int N> PS_INLINE void store(double* p, const D<N>& v) { *reinterpret_cast<typename Pack<N>::U*>(p) = v; }
template <int N> PS_INLINE V<N> operator-(const V<N>& a, const V<N>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <int N> PS_INLINE V<N> cross(const V<N>& a, const V<N>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// two lanes from two addresses: one load + one load-high
PS_INLINE D<2> pair_at(const double* a, const double* b) {
#if defined(__SSE2__)
  const __m128d v = _mm_loadh_pd(_mm_load_sd(a), b);
  return D<2>{v[0], v[1]};
#else
  return D<2>{*a, *b};
#endif
}
PS_INLINE D<2> sqrt2(const D<2>& v) {
#if defined(__SSE2__)
  const __m128d r = _mm_sqrt_pd(__m128d{v[0], v[1]});
  return D<2>{r[0], r[1]};
#else
  return D<2>{std::sqrt(v[0]), std::sqrt(v[1])};
#endif
}
template <int N> PS_INLINE D<N> sqrt_lanes(const D<N>& v) {
  if constexpr (N == 2) {
    return sqrt2(v);
  } else {
    const D<2> lo = sqrt2(D<2>{v[0], v[1]}), hi = sqrt2(D<2>{v[2], v[3]});
    return D<4>{lo[0], lo[1], hi[0], hi[1]};
  }
}
// 1/sqrt(v) where v > 0, else 0 (a triangle crushed flat, or NaN: no normal, term dropped)
template <int N> PS_INLINE D<N> inv_sqrt_or_zero(const D<N>& v) {
  const M<N> ok = v > splat<N>(0.0);
  return reinterpret_cast<D<N>>(reinterpret_cast<M<N>>(splat<N>(1.0) / sqrt_lanes<N>(v)) & ok);
}

// The (up to) N triplets of one group; unused lanes repeat the last real triplet. Plain members
// rather than an array keep the pointers in registers.
template <int N> struct Group {
  const BetaTriplet *t0, *t1, *t2, *t3;  // t2, t3 only for N = 4
  PS_INLINE Group(const BetaTriplet* first, int lanes)
      : t0(first), t1(first + (lanes > 1 ? 1 : 0)), t2(first + (lanes > 2 ? 2 : lanes - 1)),
        t3(first + (lanes > 3 ? 3 : lanes - 1)) {}
};

// lane l from the double at byte offset `off` in the l-th object
template <int N, class T>
PS_INLINE D<N> lanes_at(const T* a, const T* b, const T* c, const T* d, size_t off) {
  auto at = [off](const T* o) { return reinterpret_cast<const double*>(reinterpret_cast<const char*>(o) + off); };
  if constexpr (N == 2) {
    return pair_at(at(a), at(b));
  } else {
    const D<2> lo = pair_at(at(a), at(b)), hi = pair_at(at(c), at(d));
    return D<4>{lo[0], lo[1], hi[0], hi[1]};
  }
}

template <int N> PS_INLINE V<N> gather(const Vec3* x, const Group<N>& g, int BetaTriplet::*vertex) {
  const Vec3 *a = &x[g.t0->*vertex], *b = &x[g.t1->*vertex], *c = &x[g.t2->*vertex], *d = &x[g.t3->*vertex];
  return {lanes_at<N>(a, b, c, d, 0), lanes_at<N>(a, b, c, d, sizeof(double)),
          lanes_at<N>(a, b, c, d, 2 * sizeof(double))};
}

// State::triplet_scratch holds one block of kTripletScratchFields x N doubles per group of N
// triplets of the particle at hand; these are the fields of a block, each one D<N>.
enum Field { EjX, EjY, EjZ, EkX, EkY, EkZ, NX, NY, NZ, Scale, InvLen2 };
constexpr int kFields = kTripletScratchFields;
static_assert(InvLen2 + 1 == kFields);

// Attractor pass for one group: returns b n/|n| per lane and leaves what the gradient pass needs
// in the block.
template <int N> PS_INLINE V<N> attractor_terms(const Group<N>& g, const Vec3* x, double* blk) {
  const V<N> xi = gather<N>(x, g, &BetaTriplet::i);
  const V<N> ej = gather<N>(x, g, &BetaTriplet::j) - xi;
  const V<N> ek = gather<N>(x, g, &BetaTriplet::k) - xi;
  const V<N> n = cross(ej, ek);
  const D<N> inv_len = inv_sqrt_or_zero<N>(n.x * n.x + n.y * n.y + n.z * n.z);
  const D<N> scale = lanes_at<N>(g.t0, g.t1, g.t2, g.t3, offsetof(BetaTriplet, b)) * inv_len;  // b/|n| [1]
  store<N>(blk + N * EjX, ej.x); store<N>(blk + N * EjY, ej.y); store<N>(blk + N * EjZ, ej.z);
  store<N>(blk + N * EkX, ek.x); store<N>(blk + N * EkY, ek.y); store<N>(blk + N * EkZ, ek.z);
  store<N>(blk + N * NX, n.x); store<N>(blk + N * NY, n.y); store<N>(blk + N * NZ, n.z);
  store<N>(blk + N * Scale, scale);
  store<N>(blk + N * InvLen2, inv_len * inv_len);
  return {scale * n.x, scale * n.y, scale * n.z};
}

// f_j -= a, f_k += b, f_i += c for the triplet in lane L; x and y as one 2-lane operation
template <int L, int N>
PS_INLINE void scatter_lane(const BetaTriplet& t, const V<N>& a, const V<N>& b, const V<N>& c, Vec3* f) {
  double* fj = f[t.j].data();
  store<2>(fj, load<2>(fj) - D<2>{a.x[L], a.y[L]});
  fj[2] -= a.z[L];
  double* fk = f[t.k].data();
  store<2>(fk, load<2>(fk) + D<2>{b.x[L], b.y[L]});
  fk[2] += b.z[L];
  double* fi = f[t.i].data();
  store<2>(fi, load<2>(fi) + D<2>{c.x[L], c.y[L]});
  fi[2] += c.z[L];
}

// Gradient pass for one group. d(b n/|n|)/dx_q transposed applied to F: with
// Fp = b/|n| (F - (n.F) n/|n|^2),
//   f_j -= e_k x Fp,  f_k += e_j x Fp,  f_i += (e_k x Fp - e_j x Fp).
// Only the first `lanes` lanes are real triplets.
template <int N>
PS_INLINE void gradient_terms(const Group<N>& g, const V<N>& F, const double* blk, int lanes, Vec3* f) {
  const V<N> ej{load<N>(blk + N * EjX), load<N>(blk + N * EjY), load<N>(blk + N * EjZ)};
  const V<N> ek{load<N>(blk + N * EkX), load<N>(blk + N * EkY), load<N>(blk + N * EkZ)};
  const V<N> n{load<N>(blk + N * NX), load<N>(blk + N * NY), load<N>(blk + N * NZ)};
  const D<N> scale = load<N>(blk + N * Scale);
  const D<N> c = (n.x * F.x + n.y * F.y + n.z * F.z) * load<N>(blk + N * InvLen2);
  const V<N> Fp{scale * (F.x - c * n.x), scale * (F.y - c * n.y), scale * (F.z - c * n.z)};
  const V<N> fj = cross(ek, Fp), fk = cross(ej, Fp);
  const V<N> fi = fj - fk;
  scatter_lane<0, N>(*g.t0, fj, fk, fi, f);
  if (lanes > 1) scatter_lane<1, N>(*g.t1, fj, fk, fi, f);
  if constexpr (N == 4) {
    if (lanes > 2) scatter_lane<2, N>(*g.t2, fj, fk, fi, f);
    if (lanes > 3) scatter_lane<3, N>(*g.t3, fj, fk, fi, f);
  }
}

// Beta terms of P* for `count` triplets from bt, in groups of N, summed per lane; leaves the
// scratch for gradient_pass. Returns sum_t b_t n_t/|n_t|.
template <int N> PS_INLINE Vec3 attractor_pass(const BetaTriplet* bt, int count, const Vec3* x, double* sc) {
  V<N> acc{splat<N>(0.0), splat<N>(0.0), splat<N>(0.0)};
  int u = 0;
  for (; u + N <= count; u += N) {
    const V<N> term = attractor_terms<N>(Group<N>(bt + u, N), x, sc + u * kFields);
    acc = {acc.x + term.x, acc.y + term.y, acc.z + term.z};
  }
  if (u < count) {  // partial group: only the real lanes are added (bitwise select)
    const int lanes = count - u;
    const V<N> term = attractor_terms<N>(Group<N>(bt + u, lanes), x, sc + u * kFields);
    const M<N> real = Pack<N>::iota < (M<N>{} + lanes);
    auto add = [&](const D<N>& a, const D<N>& t) {
      return reinterpret_cast<D<N>>((reinterpret_cast<M<N>>(a + t) & real) | (reinterpret_cast<M<N>>(a) & ~real));
    };
    acc = {add(acc.x, term.x), add(acc.y, term.y), add(acc.z, term.z)};
  }
  if constexpr (N == 2) return Vec3(acc.x[0] + acc.x[1], acc.y[0] + acc.y[1], acc.z[0] + acc.z[1]);
  else
    return Vec3((acc.x[0] + acc.x[1]) + (acc.x[2] + acc.x[3]), (acc.y[0] + acc.y[1]) + (acc.y[2] + acc.y[3]),
                (acc.z[0] + acc.z[1]) + (acc.z[2] + acc.z[3]));
}

template <int N>
PS_INLINE void gradient_pass(const BetaTriplet* bt, int count, const Vec3& F, const double* sc, Vec3* f) {
  const V<N> F4{splat<N>(F[0]), splat<N>(F[1]), splat<N>(F[2])};
  int u = 0;
  for (; u + N <= count; u += N) gradient_terms<N>(Group<N>(bt + u, N), F4, sc + u * kFields, N, f);
  if (u < count) gradient_terms<N>(Group<N>(bt + u, count - u), F4, sc + u * kFields, count - u, f);
}

// Groups of 4 pay off where particles have many triplets (a mesh-based body: surface particles
// have ~8 neighbours, 28 beta triplets per particle on average for the truth cylinder); lattice
// particles (<= 8 triplets) run faster in pairs. One group size per model, chosen from the model
// alone (so every machine sums the same way), keeps a single tight loop.
constexpr int kQuadsFromTripletsPerParticle = 12;

PS_INLINE bool use_quads(const Model& m) {
  return m.beta.size() >= static_cast<size_t>(kQuadsFromTripletsPerParticle) * m.rest_pos.size();
}

template <int N> PS_INLINE void shape_memory_impl(const Model& m, State& s) {
  // raw pointers: through m and s the compiler would reload every vector's buffer after each store
  const int n = m.particle_count();
  const Vec3* x = s.x.data();
  Vec3* f = s.f.data();
  Vec3* attractor = s.attractor.data();
  const uint8_t* has_memory = m.shape_memory.data();
  const int* nbr_start = m.nbr_start.data();
  const int* nbr = m.nbr.data();
  const double* nbr_w = m.nbr_w.data();
  const int* beta_start = m.beta_start.data();
  const BetaTriplet* beta = m.beta.data();
  const double* k_e = m.k_e.data();
  const bool gradient = m.redistribution == Redistribution::Gradient;
  int cap = static_cast<int>(s.triplet_scratch.size() / kFields);  // triplets it can hold
  double* sc = s.triplet_scratch.data();
  for (int p = 0; p < n; ++p) {
    if (!has_memory[p]) continue;
    const int ns = nbr_start[p], ne = nbr_start[p + 1];
    const int bs = beta_start[p], count = beta_start[p + 1] - bs;
    if (count > cap) {  // only for a State not made by make_state(): sized once, then reused
      cap = (count + 3) / 4 * 4;
      s.triplet_scratch.assign(static_cast<size_t>(kFields) * cap, 0.0);
      sc = s.triplet_scratch.data();
    }
    const BetaTriplet* bt = beta + bs;

    Vec3 target = Vec3::Zero();
    for (int a = ns; a < ne; ++a) target += nbr_w[a] * x[nbr[a]];
    if (count > 0) target += attractor_pass<N>(bt, count, x, sc);
    attractor[p] = target;

    const Vec3 F = k_e[p] * (target - x[p]);
    f[p] += F;
    for (int a = ns; a < ne; ++a) f[nbr[a]] -= nbr_w[a] * F;
    if (gradient && count > 0) gradient_pass<N>(bt, count, F, sc, f);
  }
}

#if PS_AVX_DISPATCH
// The same code with 256-bit registers; run only where the CPU (and OS) support AVX.
template <int N> __attribute__((target("avx"))) void shape_memory_avx(const Model& m, State& s) {
  shape_memory_impl<N>(m, s);
}
#endif

}  // namespace

namespace detail {
// The baseline build, callable directly so the bench can check it against the AVX one.
void add_shape_memory_forces_baseline(const Model& m, State& s) {
  if (use_quads(m)) shape_memory_impl<4>(m, s);
  else shape_memory_impl<2>(m, s);
}
}  // namespace detail

void add_shape_memory_forces(const Model& m, State& s) {
#if PS_AVX_DISPATCH
  static const bool avx = __builtin_cpu_supports("avx");
  if (avx) {
    if (use_quads(m)) shape_memory_avx<4>(m, s);
    else shape_memory_avx<2>(m, s);
    return;
  }
#endif
  detail::add_shape_memory_forces_baseline(m, s);
}

}  // namespace ps
