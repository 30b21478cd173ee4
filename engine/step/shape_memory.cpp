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
// Speed (docs/performance.md): this stage is ~80-95% of a step. The beta triplets of a particle
// are processed two at a time in SSE2 lanes (x86-64 baseline, no -march needed): one square root
// and one division per triplet instead of five long-latency operations, and the gradient pass
// reuses the edges, normal, b/|n| and 1/|n|^2 the attractor pass left in State::triplet_scratch.
// Every lane does the same IEEE operations in the same order as the scalar fallback (a lone
// last triplet runs in lane 0 with a copy of itself in lane 1, which is discarded), so results
// do not depend on the pairing or on SSE2 being present. Force scatters keep the original
// order (triplet by triplet, j then k then i).

#include <cmath>

#include "engine/step/stages.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ps {

namespace {

// Two doubles, one per lane (a triplet each).
#if defined(__SSE2__)
struct D2 { __m128d v; };
inline D2 pair(double a, double b) { return {_mm_set_pd(b, a)}; }
inline D2 splat(double a) { return {_mm_set1_pd(a)}; }
inline D2 load(const double* p) { return {_mm_loadu_pd(p)}; }
inline void store(double* p, D2 a) { _mm_storeu_pd(p, a.v); }
inline D2 operator+(D2 a, D2 b) { return {_mm_add_pd(a.v, b.v)}; }
inline D2 operator-(D2 a, D2 b) { return {_mm_sub_pd(a.v, b.v)}; }
inline D2 operator*(D2 a, D2 b) { return {_mm_mul_pd(a.v, b.v)}; }
// 1/sqrt(x) where x > 0, else 0 (a triangle crushed flat, or NaN: no normal, term dropped)
inline D2 inv_sqrt_or_zero(D2 x) {
  const __m128d ok = _mm_cmpgt_pd(x.v, _mm_setzero_pd());
  return {_mm_and_pd(ok, _mm_div_pd(_mm_set1_pd(1.0), _mm_sqrt_pd(x.v)))};
}
inline D2 add_lane0(D2 acc, D2 x) { return {_mm_add_sd(acc.v, x.v)}; }
inline double lane0(D2 a) { return _mm_cvtsd_f64(a.v); }
inline double lane1(D2 a) { return _mm_cvtsd_f64(_mm_unpackhi_pd(a.v, a.v)); }
// f[q] += sign * (x, y, z) of one lane; xy as one packed add
template <int Lane, bool Subtract>
inline void scatter(double* fq, D2 x, D2 y, D2 z) {
  const __m128d xy = Lane == 0 ? _mm_unpacklo_pd(x.v, y.v) : _mm_unpackhi_pd(x.v, y.v);
  const __m128d old = _mm_loadu_pd(fq);
  _mm_storeu_pd(fq, Subtract ? _mm_sub_pd(old, xy) : _mm_add_pd(old, xy));
  const double zl = Lane == 0 ? lane0(z) : lane1(z);
  fq[2] = Subtract ? fq[2] - zl : fq[2] + zl;
}
#else
struct D2 { double a, b; };
inline D2 pair(double a, double b) { return {a, b}; }
inline D2 splat(double a) { return {a, a}; }
inline D2 load(const double* p) { return {p[0], p[1]}; }
inline void store(double* p, D2 x) { p[0] = x.a; p[1] = x.b; }
inline D2 operator+(D2 x, D2 y) { return {x.a + y.a, x.b + y.b}; }
inline D2 operator-(D2 x, D2 y) { return {x.a - y.a, x.b - y.b}; }
inline D2 operator*(D2 x, D2 y) { return {x.a * y.a, x.b * y.b}; }
inline double inv_sqrt_or_zero1(double x) { return x > 0.0 ? 1.0 / std::sqrt(x) : 0.0; }
inline D2 inv_sqrt_or_zero(D2 x) { return {inv_sqrt_or_zero1(x.a), inv_sqrt_or_zero1(x.b)}; }
inline D2 add_lane0(D2 acc, D2 x) { return {acc.a + x.a, acc.b}; }
inline double lane0(D2 x) { return x.a; }
inline double lane1(D2 x) { return x.b; }
template <int Lane, bool Subtract>
inline void scatter(double* fq, D2 x, D2 y, D2 z) {
  const double v[3] = {Lane == 0 ? x.a : x.b, Lane == 0 ? y.a : y.b, Lane == 0 ? z.a : z.b};
  for (int c = 0; c < 3; ++c) fq[c] = Subtract ? fq[c] - v[c] : fq[c] + v[c];
}
#endif

// Two builds of the stage, picked once at load time by the CPU: the AVX one runs the same SSE2
// operations VEX-encoded (three-operand, memory operands need no alignment: ~17% fewer
// instructions). "avx" brings no FMA, so both builds round identically (bit-identical states;
// never widen this to a target with FMA, or contraction would change results by machine).
#if defined(__x86_64__) && defined(__GNUC__) && defined(__ELF__)
#define PS_SIMD_CLONES __attribute__((target_clones("avx", "default")))
#else
#define PS_SIMD_CLONES
#endif

struct V2 { D2 x, y, z; };  // a 3-vector per lane
inline V2 operator-(const V2& a, const V2& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V2 cross(const V2& a, const V2& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline V2 gather(const Vec3* x, int a, int b) {
  return {pair(x[a][0], x[b][0]), pair(x[a][1], x[b][1]), pair(x[a][2], x[b][2])};
}

// State::triplet_scratch holds one block of kTripletScratchFields pairs of doubles per pair of
// triplets of the particle at hand (the block of triplets 2q, 2q+1 starts at 2 q kFields); these
// are the fields of a block, each one D2.
enum Field { EjX, EjY, EjZ, EkX, EkY, EkZ, NX, NY, NZ, Scale, InvLen2 };
constexpr int kFields = kTripletScratchFields;
static_assert(InvLen2 + 1 == kFields);

// Attractor pass for triplets t (lane 0) and u (lane 1) at scratch slot `slot`: returns
// b n/|n| per lane and leaves the values the gradient pass needs in the scratch.
[[gnu::always_inline]] inline V2 attractor_terms(const BetaTriplet& t, const BetaTriplet& u, const Vec3* x, double* blk) {
  const V2 xi = gather(x, t.i, u.i);
  const V2 ej = gather(x, t.j, u.j) - xi;
  const V2 ek = gather(x, t.k, u.k) - xi;
  const V2 n = cross(ej, ek);
  const D2 inv_len = inv_sqrt_or_zero(n.x * n.x + n.y * n.y + n.z * n.z);
  const D2 scale = pair(t.b, u.b) * inv_len;  // b/|n| [1]
  store(blk + 2 * EjX, ej.x); store(blk + 2 * EjY, ej.y); store(blk + 2 * EjZ, ej.z);
  store(blk + 2 * EkX, ek.x); store(blk + 2 * EkY, ek.y); store(blk + 2 * EkZ, ek.z);
  store(blk + 2 * NX, n.x); store(blk + 2 * NY, n.y); store(blk + 2 * NZ, n.z);
  store(blk + 2 * Scale, scale);
  store(blk + 2 * InvLen2, inv_len * inv_len);
  return {scale * n.x, scale * n.y, scale * n.z};
}

// Gradient pass for the two triplets at scratch slot `slot`. d(b n/|n|)/dx_q transposed applied
// to F: with Fp = b/|n| (F - (n.F) n/|n|^2),
//   f_j -= e_k x Fp,  f_k += e_j x Fp,  f_i += (e_k x Fp - e_j x Fp).
// `lanes` = 2, or 1 for a lone last triplet (lane 1 is then discarded).
[[gnu::always_inline]] inline void gradient_terms(const BetaTriplet& t, const BetaTriplet& u, const V2& F, const double* blk, int lanes,
                           Vec3* f) {
  const V2 ej{load(blk + 2 * EjX), load(blk + 2 * EjY), load(blk + 2 * EjZ)};
  const V2 ek{load(blk + 2 * EkX), load(blk + 2 * EkY), load(blk + 2 * EkZ)};
  const V2 n{load(blk + 2 * NX), load(blk + 2 * NY), load(blk + 2 * NZ)};
  const D2 scale = load(blk + 2 * Scale);
  const D2 c = (n.x * F.x + n.y * F.y + n.z * F.z) * load(blk + 2 * InvLen2);
  const V2 Fp{scale * (F.x - c * n.x), scale * (F.y - c * n.y), scale * (F.z - c * n.z)};
  const V2 fj = cross(ek, Fp), fk = cross(ej, Fp);
  const V2 fi = fj - fk;
  scatter<0, true>(f[t.j].data(), fj.x, fj.y, fj.z);
  scatter<0, false>(f[t.k].data(), fk.x, fk.y, fk.z);
  scatter<0, false>(f[t.i].data(), fi.x, fi.y, fi.z);
  if (lanes < 2) return;
  scatter<1, true>(f[u.j].data(), fj.x, fj.y, fj.z);
  scatter<1, false>(f[u.k].data(), fk.x, fk.y, fk.z);
  scatter<1, false>(f[u.i].data(), fi.x, fi.y, fi.z);
}

}  // namespace

PS_SIMD_CLONES void add_shape_memory_forces(const Model& m, State& s) {
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
      cap = (count + 1) & ~1;
      s.triplet_scratch.assign(static_cast<size_t>(kFields) * cap, 0.0);
      sc = s.triplet_scratch.data();
    }

    Vec3 target = Vec3::Zero();
    for (int a = ns; a < ne; ++a) target += nbr_w[a] * x[nbr[a]];
    // beta terms: even and odd triplets summed in separate lanes, then added together
    V2 acc{splat(0.0), splat(0.0), splat(0.0)};
    int u = 0;
    for (; u + 1 < count; u += 2) {
      const V2 term = attractor_terms(beta[bs + u], beta[bs + u + 1], x, sc + u * kFields);
      acc = {acc.x + term.x, acc.y + term.y, acc.z + term.z};
    }
    if (u < count) {
      const V2 term = attractor_terms(beta[bs + u], beta[bs + u], x, sc + u * kFields);
      acc = {add_lane0(acc.x, term.x), add_lane0(acc.y, term.y), add_lane0(acc.z, term.z)};
    }
    if (count > 0) target += Vec3(lane0(acc.x) + lane1(acc.x), lane0(acc.y) + lane1(acc.y), lane0(acc.z) + lane1(acc.z));
    attractor[p] = target;

    const Vec3 F = k_e[p] * (target - x[p]);
    f[p] += F;
    for (int a = ns; a < ne; ++a) f[nbr[a]] -= nbr_w[a] * F;
    if (!gradient) continue;
    const V2 F2{splat(F[0]), splat(F[1]), splat(F[2])};
    for (u = 0; u + 1 < count; u += 2) gradient_terms(beta[bs + u], beta[bs + u + 1], F2, sc + u * kFields, 2, f);
    if (u < count) gradient_terms(beta[bs + u], beta[bs + u], F2, sc + u * kFields, 1, f);
  }
}

}  // namespace ps
