// Elastic force of the shell model (material `model: shell`, docs/model.md "Shell model"): the
// bladder and rectal walls as thin shells on their own surface triangulation (Model::shells).
//
// Membrane, per triangle: the in-plane deformation gradient F = [x1-x0, x2-x0] Dm^-1 (3x2), its
// polar decomposition F = R S (R: 3x2 with orthonormal columns, S = sqrt(F^T F), 2x2), and the
// co-rotational linear energy of plane stress
//   E_t = A0 t [ mu |S - I|^2 + lambda/2 (tr S - 2)^2 ]
// whose exact gradient is dE/dF = A0 t R sigma, sigma = 2 mu (S - I) + lambda (tr S - 2) I, because
// d|F - R|^2/dF = 2 (F - R) and d tr S / dF = R. It is stress-free at rest, invariant under
// rotation, and Hooke's law of a plate of thickness t for small strain. A collapsed triangle
// (det F^T F ~ 0, no polar decomposition) takes the Saint Venant-Kirchhoff stress F (lambda tr E I
// + 2 mu E) of the same moduli instead, which pushes it open again.
// Bending, per interior edge: E_h = 1/2 k_h (theta - theta0)^2 on the signed dihedral angle.
// Why a shell and not the paper's attractor for the walls: the wall is ~3 mm thick while its
// particles are 7-8 mm apart, and the paper's term (45 triplets per particle) gives the wall a
// stiffness-to-mass ratio that set the whole scene's substep (0.21 ms). Plate theory gives the
// wall its real in-plane and bending stiffness for its real thickness, at a few flops per face.
// No allocation, no branch on data except the collapsed-triangle guard.
#include <cmath>

#include "engine/model/shell_elements.h"
#include "engine/step/simd_lanes.h"
#include "engine/step/stages.h"
#include "engine/util/multiversion.h"

// the 4-lane helpers' vector returns (see "Four lanes" below)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace ps {

namespace {

constexpr double kPi = 3.14159265358979323846;

inline double wrap_angle(double d) {  // into (-pi, pi]
  if (d > kPi) d -= 2.0 * kPi;
  else if (d <= -kPi) d += 2.0 * kPi;
  return d;
}

// In-plane kinematics of triangle t: F (columns a, b), and the first Piola stress times A0 t
// (columns pa, pb) [N m]; returns the energy A0 t psi [J].
inline double membrane(const ShellElements& sh, const Vec3* x, int t, Vec3& a, Vec3& b, Vec3& pa, Vec3& pb) {
  const int* v = &sh.tri[3 * t];
  const double* B = &sh.bm[4 * t];
  const Vec3 d1 = x[v[1]] - x[v[0]], d2 = x[v[2]] - x[v[0]];
  a = d1 * B[0] + d2 * B[2];  // F(:,0) = d1 Bm(0,0) + d2 Bm(1,0)
  b = d1 * B[1] + d2 * B[3];  // F(:,1)
  const double c00 = a.dot(a), c01 = a.dot(b), c11 = b.dot(b);
  const double det = c00 * c11 - c01 * c01;
  const double mu = sh.mu[t], lam = sh.lambda[t], at = sh.area_t[t];
  if (!(det > 1e-12)) {
    // collapsed: Saint Venant-Kirchhoff, E = (C - I)/2, S = lam tr E I + 2 mu E, P = F S
    const double e00 = 0.5 * (c00 - 1.0), e01 = 0.5 * c01, e11 = 0.5 * (c11 - 1.0), tr = e00 + e11;
    const double s00 = lam * tr + 2.0 * mu * e00, s01 = 2.0 * mu * e01, s11 = lam * tr + 2.0 * mu * e11;
    pa = at * (a * s00 + b * s01);
    pb = at * (a * s01 + b * s11);
    return at * (mu * (e00 * e00 + 2.0 * e01 * e01 + e11 * e11) + 0.5 * lam * tr * tr);
  }
  // S = sqrt(C) = (C + s I) / tau, s = sqrt(det C), tau = sqrt(tr C + 2 s); S^-1 = adj(S) / s
  const double s = std::sqrt(det), tau = std::sqrt(c00 + c11 + 2.0 * s);
  const double S00 = (c00 + s) / tau, S01 = c01 / tau, S11 = (c11 + s) / tau;
  const double detS = S00 * S11 - S01 * S01;
  const double i00 = S11 / detS, i01 = -S01 / detS, i11 = S00 / detS;
  const Vec3 r0 = a * i00 + b * i01, r1 = a * i01 + b * i11;  // R = F S^-1
  const double trm = S00 + S11 - 2.0;
  const double g00 = 2.0 * mu * (S00 - 1.0) + lam * trm, g01 = 2.0 * mu * S01, g11 = 2.0 * mu * (S11 - 1.0) + lam * trm;
  pa = at * (r0 * g00 + r1 * g01);
  pb = at * (r0 * g01 + r1 * g11);
  return at * (mu * ((S00 - 1.0) * (S00 - 1.0) + 2.0 * S01 * S01 + (S11 - 1.0) * (S11 - 1.0)) + 0.5 * lam * trm * trm);
}

// atan2(s, c) [rad]. A hinge's bend away from its rest angle is small nearly always, and there
// glibc's atan2 (correctly rounded, with its range and special-case handling) would be the
// largest single cost of the shell stage (~11 % of a biopsy tick in perf). For |s| <= c / 4 (within 14
// degrees) atan(s / c) is its odd Taylor series to z^25: the first term left out, |z|^27 / 27,
// is below 8.3e-18 |z|, under half an ulp; the sum is in Estrin's form (short dependency chains).
// Anything else goes to std::atan2.
// atan_series: atan(z) for |z| <= 1/4 by that series, for a double or four lanes of them (the
// hinge passes below: the same operations in the same order either way; always inlined, so the
// 4-lane form never crosses a call)
template <class T>
inline __attribute__((always_inline)) T atan_series(T z) {
  const T w = z * z, w2 = w * w, w4 = w2 * w2, w8 = w4 * w4;
  // a_k = (-1)^k / (2k + 1), as constants (a division by 3.0 would be a division instruction)
  constexpr double a1 = 1.0 / 3, a2 = 1.0 / 5, a3 = 1.0 / 7, a4 = 1.0 / 9, a5 = 1.0 / 11, a6 = 1.0 / 13, a7 = 1.0 / 15;
  constexpr double a8 = 1.0 / 17, a9 = 1.0 / 19, a10 = 1.0 / 21, a11 = 1.0 / 23, a12 = 1.0 / 25;
  const T q0 = 1.0 - w * a1, q1 = a2 - w * a3, q2 = a4 - w * a5, q3 = a6 - w * a7;
  const T q4 = a8 - w * a9, q5 = a10 - w * a11;
  const T r0 = q0 + q1 * w2, r1 = q2 + q3 * w2, r2 = q4 + q5 * w2;
  return z * ((r0 + r1 * w4) + (r2 + a12 * w4) * w8);
}

// the series' range: within 14 degrees, in the right half-plane
inline bool atan_series_holds(double s, double c) { return c > 0.0 && std::abs(s) <= 0.25 * c; }

inline double atan2_small(double s, double c) { return atan_series_holds(s, c) ? atan_series(s / c) : std::atan2(s, c); }

// The hinge's bend theta - theta0 from its rest angle, in (-pi, pi] [rad], given cos and sin of
// theta0 (ShellElements::rest_cs), and its gradient grad[4] = d theta / d x_i [1/m].
inline double hinge_bend(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, double cos0, double sin0, Vec3* grad) {
  // hinge_angle's terms (engine/model/shell_elements.cpp) with fewer divisions, inline in the
  // force loop: the angle's direction is scale-free, so (x |e|, y |e|) replaces (x, y)
  const Vec3 e = x1 - x0;
  const Vec3 n1 = e.cross(x2 - x0);
  const Vec3 n2 = (x0 - x1).cross(x3 - x1);
  const double le2 = e.squaredNorm(), le = std::sqrt(le2), inv_le2 = 1.0 / le2;
  const double ys = n1.cross(n2).dot(e), xs = n1.dot(n2) * le;
  const Vec3 u2 = -le / n1.squaredNorm() * n1;
  const Vec3 u3 = -le / n2.squaredNorm() * n2;
  const double a1 = (x2 - x0).dot(e) * inv_le2, a2 = (x3 - x0).dot(e) * inv_le2;
  grad[0] = -(1.0 - a1) * u2 - (1.0 - a2) * u3;
  grad[1] = -a1 * u2 - a2 * u3;
  grad[2] = u2;
  grad[3] = u3;
  // (x, y) turned back by theta0: its direction is theta - theta0, already in (-pi, pi]
  return atan2_small(ys * cos0 - xs * sin0, xs * cos0 + ys * sin0);
}

}  // namespace

namespace {

// triangle t's membrane force, added to f (the scalar pass; the 4-lane one below does exactly
// these operations)
inline void membrane_force(const ShellElements& sh, const Vec3* x, int t, Vec3* f) {
  Vec3 a, b, pa, pb;
  membrane(sh, x, t, a, b, pa, pb);
  // dE/dx_j = P Bm^T column j: x1 <- row 0 of Bm, x2 <- row 1
  const double* B = &sh.bm[4 * t];
  const Vec3 g1 = pa * B[0] + pb * B[1];
  const Vec3 g2 = pa * B[2] + pb * B[3];
  const int* v = &sh.tri[3 * t];
  f[v[1]] -= g1;
  f[v[2]] -= g2;
  f[v[0]] += g1 + g2;
}

// hinge h's bending force, added to f (scalar)
inline void hinge_force(const ShellElements& sh, const Vec3* x, int h, Vec3* f) {
  const int* v = &sh.hinge[4 * h];
  Vec3 g[4];
  const double bend = hinge_bend(x[v[0]], x[v[1]], x[v[2]], x[v[3]], sh.rest_cs[2 * h], sh.rest_cs[2 * h + 1], g);
  const double c = sh.k_hinge[h] * bend;  // dE/dtheta [N m]
  for (int i = 0; i < 4; ++i) f[v[i]] -= c * g[i];
}

// Four or eight lanes of the scalar passes' arithmetic (GCC vector extensions, as the tet element
// pass): each lane does the scalar operations in the scalar order (Eigen's 3-vector dot is
// (x0 y0 + x1 y1) + x2 y2, its cross the textbook one; no FMA anywhere, -ffp-contract=off), and
// the forces go to the particles lane by lane in element order, so every width gives the scalar
// pass's bits (tests/engine/step/shell_elastic_test.cpp). Square roots lane by lane (std::sqrt,
// exact; one vsqrtpd without errno, engine/CMakeLists.txt). Eight lanes (one AVX-512 register)
// where the CPU has them, as the tet element pass (tet_element_forces8_available): half the
// arithmetic instructions; the gathers and the scatter stay lane by lane.
// The helpers below are always inlined into the passes (whose clones have AVX), as is
// atan_series: their by-value vector returns never cross a call, so GCC's note on the non-AVX
// calling convention (-Wpsabi, off for this file at its top) is moot.
#define PS_LANES inline __attribute__((always_inline))
// L doubles per vector and their comparison mask (engine/step/simd_lanes.h)
template <int L> struct ShellLane {
  typedef typename LaneVector<L>::type D;
  typedef typename LaneVector<L>::mask M;
};

template <class D> struct V3 { D c[3]; };
template <class D> PS_LANES V3<D> sub(const V3<D>& a, const V3<D>& b) { return {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}}; }
template <class D> PS_LANES D dot(const V3<D>& a, const V3<D>& b) { return (a.c[0] * b.c[0] + a.c[1] * b.c[1]) + a.c[2] * b.c[2]; }
template <class D> PS_LANES V3<D> cross(const V3<D>& a, const V3<D>& b) {
  return {{a.c[1] * b.c[2] - a.c[2] * b.c[1], a.c[2] * b.c[0] - a.c[0] * b.c[2], a.c[0] * b.c[1] - a.c[1] * b.c[0]}};
}

// {v(0), ..., v(L - 1)} (lanes_of, as a value)
template <int L, class Fn>
PS_LANES typename ShellLane<L>::D lanes(Fn v) {
  typename ShellLane<L>::D out;
  lanes_of<L>(out, v);
  return out;
}
template <int L> PS_LANES typename ShellLane<L>::D sqrt_lanes(const typename ShellLane<L>::D& v) {
  return lanes<L>([&](int l) { return std::sqrt(v[l]); });
}
template <int L> PS_LANES bool all_lanes(const typename ShellLane<L>::M& m) {
  bool all = true;
  for (int l = 0; l < L; ++l) all = all && m[l];
  return all;
}

// vertex i of lanes l = 0..L-1, whose particle indices are idx[stride l + i]
template <int L>
PS_LANES V3<typename ShellLane<L>::D> gather(const Vec3* x, const int* idx, int stride, int i) {
  V3<typename ShellLane<L>::D> out;
  for (int r = 0; r < 3; ++r) out.c[r] = lanes<L>([&](int l) { return x[idx[stride * l + i]][r]; });
  return out;
}

// triangles [t, t + L): when no lane's in-plane C is collapsed, L wide; else (rare) the scalar pass
template <int L>
PS_LANES void membrane_block(const ShellElements& sh, const Vec3* x, int t, Vec3* f) {
  typedef typename ShellLane<L>::D D;
  const int* v = &sh.tri[3 * t];
  const double* Bp = &sh.bm[4 * t];
  D B[4];
  for (int i = 0; i < 4; ++i) B[i] = lanes<L>([&](int l) { return Bp[4 * l + i]; });
  const V3<D> x0 = gather<L>(x, v, 3, 0);
  const V3<D> d1 = sub(gather<L>(x, v, 3, 1), x0), d2 = sub(gather<L>(x, v, 3, 2), x0);
  V3<D> a, b;
  for (int r = 0; r < 3; ++r) {
    a.c[r] = d1.c[r] * B[0] + d2.c[r] * B[2];
    b.c[r] = d1.c[r] * B[1] + d2.c[r] * B[3];
  }
  const D c00 = dot(a, a), c01 = dot(a, b), c11 = dot(b, b);
  const D det = c00 * c11 - c01 * c01;
  if (!all_lanes<L>(det > 1e-12)) {
    for (int l = 0; l < L; ++l) membrane_force(sh, x, t + l, f);
    return;
  }
  const D mu = lanes<L>([&](int l) { return sh.mu[t + l]; });
  const D lam = lanes<L>([&](int l) { return sh.lambda[t + l]; });
  const D at = lanes<L>([&](int l) { return sh.area_t[t + l]; });
  const D sq = sqrt_lanes<L>(det), tau = sqrt_lanes<L>(c00 + c11 + 2.0 * sq);
  const D S00 = (c00 + sq) / tau, S01 = c01 / tau, S11 = (c11 + sq) / tau;
  const D detS = S00 * S11 - S01 * S01;
  const D i00 = S11 / detS, i01 = -S01 / detS, i11 = S00 / detS;
  const D trm = S00 + S11 - 2.0;
  const D g00 = 2.0 * mu * (S00 - 1.0) + lam * trm, g01 = 2.0 * mu * S01, g11 = 2.0 * mu * (S11 - 1.0) + lam * trm;
  V3<D> g1, g2;
  for (int r = 0; r < 3; ++r) {
    const D r0 = a.c[r] * i00 + b.c[r] * i01, r1 = a.c[r] * i01 + b.c[r] * i11;  // R = F S^-1
    const D pa = at * (r0 * g00 + r1 * g01), pb = at * (r0 * g01 + r1 * g11);
    g1.c[r] = pa * B[0] + pb * B[1];
    g2.c[r] = pa * B[2] + pb * B[3];
  }
  for (int l = 0; l < L; ++l) {
    const int* w = v + 3 * l;
    double* f0 = f[w[0]].data();
    double* f1 = f[w[1]].data();
    double* f2 = f[w[2]].data();
    for (int r = 0; r < 3; ++r) f1[r] -= g1.c[r][l];
    for (int r = 0; r < 3; ++r) f2[r] -= g2.c[r][l];
    for (int r = 0; r < 3; ++r) f0[r] += g1.c[r][l] + g2.c[r][l];
  }
}

// hinges [h, h + L); a lane whose bend is outside atan2_small's range takes std::atan2 for it, as
// the scalar pass does
template <int L>
PS_LANES void hinge_block(const ShellElements& sh, const Vec3* x, int h, Vec3* f) {
  typedef typename ShellLane<L>::D D;
  const int* v = &sh.hinge[4 * h];
  const V3<D> x0 = gather<L>(x, v, 4, 0), x1 = gather<L>(x, v, 4, 1), x2 = gather<L>(x, v, 4, 2), x3 = gather<L>(x, v, 4, 3);
  // hinge_bend's operations
  const V3<D> e = sub(x1, x0);
  const V3<D> n1 = cross(e, sub(x2, x0));
  const V3<D> n2 = cross(sub(x0, x1), sub(x3, x1));
  const D le2 = dot(e, e), le = sqrt_lanes<L>(le2), inv_le2 = 1.0 / le2;
  const D ys = dot(cross(n1, n2), e), xs = dot(n1, n2) * le;
  const D s2 = -le / dot(n1, n1), s3 = -le / dot(n2, n2);
  const D a1 = dot(sub(x2, x0), e) * inv_le2, a2 = dot(sub(x3, x0), e) * inv_le2;
  const double* cs = &sh.rest_cs[2 * h];
  const D cos0 = lanes<L>([&](int l) { return cs[2 * l]; }), sin0 = lanes<L>([&](int l) { return cs[2 * l + 1]; });
  const D sy = ys * cos0 - xs * sin0, cx = xs * cos0 + ys * sin0;
  // atan2_small in L lanes
  D bend = atan_series(sy / cx);
  for (int l = 0; l < L; ++l)
    if (!atan_series_holds(sy[l], cx[l])) bend[l] = std::atan2(sy[l], cx[l]);
  const D c = lanes<L>([&](int l) { return sh.k_hinge[h + l]; }) * bend;  // dE/dtheta [N m]
  V3<D> g[4];
  for (int r = 0; r < 3; ++r) {
    const D u2 = s2 * n1.c[r], u3 = s3 * n2.c[r];
    g[0].c[r] = -(1.0 - a1) * u2 - (1.0 - a2) * u3;
    g[1].c[r] = -a1 * u2 - a2 * u3;
    g[2].c[r] = u2;
    g[3].c[r] = u3;
  }
  for (int l = 0; l < L; ++l)
    for (int i = 0; i < 4; ++i) {
      double* fi = f[v[4 * l + i]].data();
      for (int r = 0; r < 3; ++r) fi[r] -= c[l] * g[i].c[r][l];
    }
}

// The two kinds of element as the range below runs them: L at a time, or one (the scalar pass)
struct Membranes {
  template <int L> static PS_LANES void block(const ShellElements& sh, const Vec3* x, int t, Vec3* f) { membrane_block<L>(sh, x, t, f); }
  static PS_LANES void one(const ShellElements& sh, const Vec3* x, int t, Vec3* f) { membrane_force(sh, x, t, f); }
};
struct Hinges {
  template <int L> static PS_LANES void block(const ShellElements& sh, const Vec3* x, int h, Vec3* f) { hinge_block<L>(sh, x, h, f); }
  static PS_LANES void one(const ShellElements& sh, const Vec3* x, int h, Vec3* f) { hinge_force(sh, x, h, f); }
};

// elements [begin, end) of one Kind in blocks of L (L = 8: then of four), the rest one at a time
template <int L, class Kind>
PS_LANES void lane_range(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  int i = begin;
  if constexpr (L == 8)
    for (; i + 8 <= end; i += 8) Kind::template block<8>(sh, x, i, f);
  for (; i + 4 <= end; i += 4) Kind::template block<4>(sh, x, i, f);
  for (; i < end; ++i) Kind::one(sh, x, i, f);
}

#undef PS_LANES

}  // namespace

// four lanes: one AVX register (AVX-512's narrow form in its clone), two SSE2 ones in the baseline
PS_TARGET_CLONES("arch=x86-64-v4", "avx", "default")
void shell_membrane_forces4(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  lane_range<4, Membranes>(sh, x, begin, end, f);
}
PS_TARGET_CLONES("arch=x86-64-v4", "avx", "default")
void shell_hinge_forces4(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  lane_range<4, Hinges>(sh, x, begin, end, f);
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(PROSTATESIM_NO_MULTIVERSION)
// eight lanes: one AVX-512 register (x86-64-v4), called only where tet_element_forces8_available()
__attribute__((target("arch=x86-64-v4")))
void shell_membrane_forces8(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  lane_range<8, Membranes>(sh, x, begin, end, f);
}
__attribute__((target("arch=x86-64-v4")))
void shell_hinge_forces8(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  lane_range<8, Hinges>(sh, x, begin, end, f);
}
#else
// no AVX-512 build (sanitizers, other compilers): four lanes, the same bits
void shell_membrane_forces8(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  shell_membrane_forces4(sh, x, begin, end, f);
}
void shell_hinge_forces8(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  shell_hinge_forces4(sh, x, begin, end, f);
}
#endif

// Membranes [begin, end) into f: blocks of eight (AVX-512) or four triangles, a block with a
// collapsed triangle (rare) by the scalar pass; the same bits at every width.
void add_shell_membrane_forces(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  if (tet_element_forces8_available()) shell_membrane_forces8(sh, x, begin, end, f);
  else shell_membrane_forces4(sh, x, begin, end, f);
}

// Hinges [begin, end) into f, eight (AVX-512) or four at a time; the same bits at every width.
void add_shell_hinge_forces(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  if (tet_element_forces8_available()) shell_hinge_forces8(sh, x, begin, end, f);
  else shell_hinge_forces4(sh, x, begin, end, f);
}
void add_shell_elastic_forces(const Model& m, State& s) {
  const ShellElements& sh = m.shells;
  add_shell_membrane_forces(sh, s.x.data(), 0, sh.triangle_count(), s.f.data());
  add_shell_hinge_forces(sh, s.x.data(), 0, sh.hinge_count(), s.f.data());
}

double shell_elastic_energy(const Model& m, const State& s) {
  const ShellElements& sh = m.shells;
  double e = 0.0;
  for (int t = 0; t < sh.triangle_count(); ++t) {
    Vec3 a, b, pa, pb;
    e += membrane(sh, s.x.data(), t, a, b, pa, pb);
  }
  for (int h = 0; h < sh.hinge_count(); ++h) {
    const int* v = &sh.hinge[4 * h];
    const double d = wrap_angle(hinge_angle(s.x[v[0]], s.x[v[1]], s.x[v[2]], s.x[v[3]]) - sh.theta0[h]);
    e += 0.5 * sh.k_hinge[h] * d * d;
  }
  return e;
}

}  // namespace ps
