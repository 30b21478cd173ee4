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
// Speed (docs/performance.md): this stage is ~90% of a step. It reads the beta triplets in the
// chunk layout of Model::chunks (engine/model/triplet_chunks.h): 4 triplets per chunk, one per
// lane of a 4-double vector (GCC vector extension), as two half-chunks of two triplets
// (a, b, c) and (a, b, c + 1) in the slots of the particle's neighbour list. The particle's
// neighbour positions are first copied to small per-slot arrays (X, Y, Z), so a chunk loads x_a
// and x_b as two broadcasts and x_c, x_c+1 as one pair per half, and the forces on the vertices go
// to per-slot accumulators (G) that reach each neighbour in one scatter with its linear share.
// Lanes that hold no beta triplet have b = 0 and add exactly zero. One square root and one
// division per triplet; the gradient pass reuses the edges, normal, b/|n| and 1/|n|^2 that the
// attractor pass left in State::triplet_scratch. The same source is compiled twice, for the
// x86-64 baseline (SSE2) and with AVX (VEX encoding, 256-bit registers), and the AVX build runs
// where the CPU has it. Lanes only ever do IEEE +, -, *, / and sqrt, "avx" brings no FMA and the
// lane layout does not depend on the build, so both builds give bit-identical forces
// (prostatesim_bench --verify checks it). Each triplet's normal and force terms are those of the
// triplet alone (its vertices possibly rotated cyclically); the order of the sums is fixed by the
// model, so every run and machine gives the same bits: the beta terms of P* are summed per lane
// over the particle's chunks and the lane sums added as (l0 + l1) + (l2 + l3), after the linear
// part (summed in neighbour order); a neighbour's force is f_q += (-w_q F + its gradient shares
// chunk by chunk).

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/model/triplet_chunks.h"
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

template <int N> PS_INLINE D<N> splat(double a) {  // a broadcast (D<N>{} + a would be an add)
  if constexpr (N == 2) return D<N>{a, a};
  else return D<N>{a, a, a, a};
}
template <int N> PS_INLINE D<N> load(const double* p) { return *reinterpret_cast<const typename Pack<N>::U*>(p); }
template <int N> PS_INLINE void store(double* p, const D<N>& v) { *reinterpret_cast<typename Pack<N>::U*>(p) = v; }
template <int N> PS_INLINE V<N> operator-(const V<N>& a, const V<N>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <int N> PS_INLINE V<N> cross(const V<N>& a, const V<N>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
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

PS_INLINE double reduce(const D<4>& v) { return (v[0] + v[1]) + (v[2] + v[3]); }

constexpr int kFields = kTripletScratchFields;  // per lane: e_j, e_k, n (3 each), b/|n|, 1/|n|^2
enum Field { EjX, EjY, EjZ, EkX, EkY, EkZ, NX, NY, NZ, Scale, InvLen2 };
static_assert(InvLen2 + 1 == kFields);

// lanes (s0, s0, s1, s1) and (s0, s0 + 1, s1, s1 + 1) of a per-slot array
PS_INLINE D<4> twice(const double* v, int s0, int s1) { return D<4>{v[s0], v[s0], v[s1], v[s1]}; }
PS_INLINE D<4> pairs(const double* v, int s0, int s1) {
  const D<2> lo = load<2>(v + s0), hi = load<2>(v + s1);
  return D<4>{lo[0], lo[1], hi[0], hi[1]};
}

// g0 += (v.x, v.y, v.z)[l0] + [l1], g1 += [l2] + [l3] (or -=; 4th component: don't care)
template <bool Subtract> PS_INLINE void add_halves(double* g0, double* g1, const V<4>& v) {
  typedef int64_t I __attribute__((vector_size(32)));
  const D<4> xy = __builtin_shuffle(v.x, v.y, I{0, 4, 2, 6}) + __builtin_shuffle(v.x, v.y, I{1, 5, 3, 7});
  const D<4> zz = __builtin_shuffle(v.z, v.z, I{0, 4, 2, 6}) + __builtin_shuffle(v.z, v.z, I{1, 5, 3, 7});
  const D<4> h0 = __builtin_shuffle(xy, zz, I{0, 1, 4, 5}), h1 = __builtin_shuffle(xy, zz, I{2, 3, 6, 7});
  if constexpr (Subtract) {
    store<4>(g0, load<4>(g0) - h0);
    store<4>(g1, load<4>(g1) - h1);
  } else {
    store<4>(g0, load<4>(g0) + h0);
    store<4>(g1, load<4>(g1) + h1);
  }
}
// g -= or += ([l0] + [l1]) + ([l2] + [l3])
template <bool Subtract> PS_INLINE void add_both(double* g, const V<4>& v) {
  typedef int64_t I __attribute__((vector_size(32)));
  const D<4> xy = __builtin_shuffle(v.x, v.y, I{0, 4, 2, 6}) + __builtin_shuffle(v.x, v.y, I{1, 5, 3, 7});
  const D<4> zz = __builtin_shuffle(v.z, v.z, I{0, 4, 2, 6}) + __builtin_shuffle(v.z, v.z, I{1, 5, 3, 7});
  const D<4> h = __builtin_shuffle(xy, zz, I{0, 1, 4, 5}) + __builtin_shuffle(xy, zz, I{2, 3, 6, 7});
  if constexpr (Subtract) store<4>(g, load<4>(g) - h);
  else store<4>(g, load<4>(g) + h);
}
// g0 += [l0] + [l2], g1 += [l1] + [l3] (both half-chunks on slots c, c + 1)
PS_INLINE void add_lanes_twice(double* g0, double* g1, const V<4>& v) {
  typedef int64_t I __attribute__((vector_size(32)));
  const D<4> xy0 = __builtin_shuffle(v.x, v.y, I{0, 4, 2, 6});  // x0 y0 x2 y2
  const D<4> xy1 = __builtin_shuffle(v.x, v.y, I{1, 5, 3, 7});  // x1 y1 x3 y3
  store<4>(g0, load<4>(g0) + (__builtin_shuffle(xy0, v.z, I{0, 1, 4, 4}) + __builtin_shuffle(xy0, v.z, I{2, 3, 6, 6})));
  store<4>(g1, load<4>(g1) + (__builtin_shuffle(xy1, v.z, I{0, 1, 5, 5}) + __builtin_shuffle(xy1, v.z, I{2, 3, 7, 7})));
}
// g_l += (v.x, v.y, v.z)[l] for the four lanes
PS_INLINE void add_lanes(double* g0, double* g1, double* g2, double* g3, const V<4>& v) {
  typedef int64_t I __attribute__((vector_size(32)));
  const D<4> xy0 = __builtin_shuffle(v.x, v.y, I{0, 4, 2, 6});  // x0 y0 x2 y2
  const D<4> xy1 = __builtin_shuffle(v.x, v.y, I{1, 5, 3, 7});  // x1 y1 x3 y3
  store<4>(g0, load<4>(g0) + __builtin_shuffle(xy0, v.z, I{0, 1, 4, 4}));
  store<4>(g1, load<4>(g1) + __builtin_shuffle(xy1, v.z, I{0, 1, 5, 5}));
  store<4>(g2, load<4>(g2) + __builtin_shuffle(xy0, v.z, I{2, 3, 6, 6}));
  store<4>(g3, load<4>(g3) + __builtin_shuffle(xy1, v.z, I{2, 3, 7, 7}));
}

PS_INLINE void shape_memory_impl(const Model& m, State& s) {
  constexpr int N = 4;
  // raw pointers: through m and s the compiler would reload every vector's buffer after each store
  const int n = m.particle_count();
  const Vec3* x = s.x.data();
  Vec3* f = s.f.data();
  Vec3* attractor = s.attractor.data();
  const uint8_t* has_memory = m.shape_memory.data();
  const int* nbr_start = m.nbr_start.data();
  const int* nbr = m.nbr.data();
  const double* nbr_w = m.nbr_w.data();
  const int* chunk_start = m.chunk_start.data();
  const TripletChunk* chunks = m.chunks.data();
  const double* chunk_beta = m.chunk_beta.data();
  const double* k_e = m.k_e.data();
  const bool gradient = m.redistribution == Redistribution::Gradient;
  const size_t need = static_cast<size_t>(kFields) * N * m.most_chunks;
  if (s.triplet_scratch.size() < need) s.triplet_scratch.assign(need, 0.0);  // only for a State not made by make_state()
  double* sc = s.triplet_scratch.data();

  // per-slot copies of the particle's neighbour positions [m] and accumulators of the gradient
  // force on them [N]; the padding slot after the last neighbour stays finite (zero or an earlier
  // neighbour), so the b = 0 lanes that read it add exactly zero
  alignas(32) double X[kChunkSlots] = {}, Y[kChunkSlots] = {}, Z[kChunkSlots] = {};
  // (x, y, z, unused) per slot; the padding slot's only ever gets zeros (b = 0 lanes) and is never read
  alignas(32) double G[kChunkSlots][4] = {};

  for (int p = 0; p < n; ++p) {
    if (!has_memory[p]) continue;
    const int ns = nbr_start[p], nn = nbr_start[p + 1] - ns;
    const int* nb = nbr + ns;
    const double* w = nbr_w + ns;
    double tx = 0, ty = 0, tz = 0;  // linear part of P*, neighbour order
    for (int a = 0; a < nn; ++a) {
      const double* q = x[nb[a]].data();
      X[a] = q[0]; Y[a] = q[1]; Z[a] = q[2];
      tx += w[a] * q[0]; ty += w[a] * q[1]; tz += w[a] * q[2];
    }
    const TripletChunk* c0 = chunks + chunk_start[p];
    const TripletChunk* c1 = chunks + chunk_start[p + 1];

    // attractor pass: sum_t b_t n_t/|n_t|, per lane
    const D<N> zero = splat<N>(0.0);
    V<N> acc{zero, zero, zero};
    const double* bb = chunk_beta + N * chunk_start[p];
    double* blk = sc;
    for (const TripletChunk* c = c0; c != c1; ++c, bb += N, blk += N * kFields) {
      const int a0 = c->a[0], a1 = c->a[1], b0 = c->b[0], b1 = c->b[1], k0 = c->c[0], k1 = c->c[1];
      const V<N> xa{twice(X, a0, a1), twice(Y, a0, a1), twice(Z, a0, a1)};
      const V<N> ej = V<N>{twice(X, b0, b1), twice(Y, b0, b1), twice(Z, b0, b1)} - xa;
      const V<N> ek = V<N>{pairs(X, k0, k1), pairs(Y, k0, k1), pairs(Z, k0, k1)} - xa;
      const V<N> nv = cross(ej, ek);
      const D<N> inv_len = inv_sqrt_or_zero<N>(nv.x * nv.x + nv.y * nv.y + nv.z * nv.z);
      const D<N> scale = load<N>(bb) * inv_len;  // b/|n| [1]
      store<N>(blk + N * EjX, ej.x); store<N>(blk + N * EjY, ej.y); store<N>(blk + N * EjZ, ej.z);
      store<N>(blk + N * EkX, ek.x); store<N>(blk + N * EkY, ek.y); store<N>(blk + N * EkZ, ek.z);
      store<N>(blk + N * NX, nv.x); store<N>(blk + N * NY, nv.y); store<N>(blk + N * NZ, nv.z);
      store<N>(blk + N * Scale, scale);
      store<N>(blk + N * InvLen2, inv_len * inv_len);
      acc = {acc.x + scale * nv.x, acc.y + scale * nv.y, acc.z + scale * nv.z};
    }
    if (c0 != c1) { tx += reduce(acc.x); ty += reduce(acc.y); tz += reduce(acc.z); }
    attractor[p] = Vec3(tx, ty, tz);

    const double ke = k_e[p];
    const double Fx = ke * (tx - x[p][0]), Fy = ke * (ty - x[p][1]), Fz = ke * (tz - x[p][2]);
    f[p] += Vec3(Fx, Fy, Fz);
    if (!gradient || c0 == c1) {
      for (int a = 0; a < nn; ++a) f[nb[a]] -= w[a] * Vec3(Fx, Fy, Fz);
      continue;
    }

    // gradient pass. d(b n/|n|)/dx_q transposed applied to F: with Fp = b/|n| (F - (n.F) n/|n|^2),
    //   f_b -= e_k x Fp,  f_c += e_j x Fp,  f_a += (e_k x Fp - e_j x Fp).
    const V<N> F{splat<N>(Fx), splat<N>(Fy), splat<N>(Fz)};
    const D<N> F4{Fx, Fy, Fz, 0.0};
    for (int a = 0; a < nn; ++a) store<N>(G[a], splat<N>(-w[a]) * F4);  // the linear share first
    double* g = &G[0][0];
    blk = sc;
    for (const TripletChunk* c = c0; c != c1; ++c, blk += N * kFields) {
      const V<N> ej{load<N>(blk + N * EjX), load<N>(blk + N * EjY), load<N>(blk + N * EjZ)};
      const V<N> ek{load<N>(blk + N * EkX), load<N>(blk + N * EkY), load<N>(blk + N * EkZ)};
      const V<N> nv{load<N>(blk + N * NX), load<N>(blk + N * NY), load<N>(blk + N * NZ)};
      const D<N> scale = load<N>(blk + N * Scale);
      const D<N> cf = (nv.x * F.x + nv.y * F.y + nv.z * F.z) * load<N>(blk + N * InvLen2);
      const V<N> Fp{scale * (F.x - cf * nv.x), scale * (F.y - cf * nv.y), scale * (F.z - cf * nv.z)};
      // fb = -(e_k x Fp) exactly (x - y = -(y - x) in IEEE), and the share of a is -(fb + fk)
      const V<N> fb = cross(Fp, ek), fk = cross(ej, Fp);
      const V<N> fs{fb.x + fk.x, fb.y + fk.y, fb.z + fk.z};
      // to per-slot (x, y, z, -) accumulators: the c lanes one slot each, the a and b lanes summed
      // per half-chunk (l0 + l1, l2 + l3), as whole vectors (transposed by shuffles)
      // both half-chunks on the same slots (lattices: the common case) add their halves first
      if (c->a4[0] == c->a4[1]) add_both<true>(g + c->a4[0], fs);
      else add_halves<true>(g + c->a4[0], g + c->a4[1], fs);
      add_halves<false>(g + c->b4[0], g + c->b4[1], fb);
      if (c->c4[0] == c->c4[1]) add_lanes_twice(g + c->c4[0], g + c->c4[0] + 4, fk);
      else add_lanes(g + c->c4[0], g + c->c4[0] + 4, g + c->c4[1], g + c->c4[1] + 4, fk);
    }
    for (int a = 0; a < nn; ++a) {  // f_q += -w_q F + (gradient shares)
      double* fq = f[nb[a]].data();
      store<2>(fq, load<2>(fq) + load<2>(G[a]));
      fq[2] += G[a][2];
    }
  }
}

#if PS_AVX_DISPATCH
// The same code with 256-bit registers; run only where the CPU (and OS) support AVX.
__attribute__((target("avx"))) void shape_memory_avx(const Model& m, State& s) { shape_memory_impl(m, s); }
#endif

}  // namespace

namespace detail {
// The baseline build, callable directly so the bench can check it against the AVX one.
void add_shape_memory_forces_baseline(const Model& m, State& s) {
  shape_memory_impl(m, s);
}
}  // namespace detail

void add_shape_memory_forces(const Model& m, State& s) {
#if PS_AVX_DISPATCH
  static const bool avx = __builtin_cpu_supports("avx");
  if (avx) {
    shape_memory_avx(m, s);
    return;
  }
#endif
  detail::add_shape_memory_forces_baseline(m, s);
}

}  // namespace ps
