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
// glibc's atan2 (correctly rounded, with its range and special-case handling) was the largest
// single cost of the shell stage (~11 % of a biopsy tick in perf). For |s| <= c / 4 (within 14
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

// Four lanes of the scalar passes' arithmetic (GCC vector extensions, as the tet element pass):
// each lane does the scalar operations in the scalar order (Eigen's 3-vector dot is
// (x0 y0 + x1 y1) + x2 y2, its cross the textbook one; no FMA anywhere, -ffp-contract=off), and
// the forces go to the particles lane by lane in element order, so both give the same bits
// (tests/engine/step/shell_elastic_test.cpp). Square roots lane by lane (std::sqrt, exact).
// The helpers below are always inlined into the passes (whose clones have AVX), as is
// atan_series: their by-value vector returns never cross a call, so GCC's note on the non-AVX
// calling convention (-Wpsabi, off for this file at its top) is moot.
#define PS_LANES inline __attribute__((always_inline))
typedef double D4 __attribute__((vector_size(32)));
typedef long long L4 __attribute__((vector_size(32)));

struct V3 { D4 c[3]; };
PS_LANES V3 sub(const V3& a, const V3& b) { return {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}}; }
PS_LANES D4 dot(const V3& a, const V3& b) { return (a.c[0] * b.c[0] + a.c[1] * b.c[1]) + a.c[2] * b.c[2]; }
PS_LANES V3 cross(const V3& a, const V3& b) {
  return {{a.c[1] * b.c[2] - a.c[2] * b.c[1], a.c[2] * b.c[0] - a.c[0] * b.c[2], a.c[0] * b.c[1] - a.c[1] * b.c[0]}};
}
PS_LANES D4 sqrt4(D4 v) { return D4{std::sqrt(v[0]), std::sqrt(v[1]), std::sqrt(v[2]), std::sqrt(v[3])}; }
PS_LANES bool all4(L4 m) { return m[0] && m[1] && m[2] && m[3]; }

// vertex i of lanes l = 0..3, whose particle indices are idx[stride l + i]
PS_LANES V3 gather(const Vec3* x, const int* idx, int stride, int i) {
  const double* p0 = x[idx[i]].data();
  const double* p1 = x[idx[stride + i]].data();
  const double* p2 = x[idx[2 * stride + i]].data();
  const double* p3 = x[idx[3 * stride + i]].data();
  return {{D4{p0[0], p1[0], p2[0], p3[0]}, D4{p0[1], p1[1], p2[1], p3[1]}, D4{p0[2], p1[2], p2[2], p3[2]}}};
}

#undef PS_LANES

}  // namespace

// Membranes [begin, end) into f: blocks of four triangles whose in-plane C is not collapsed in
// any lane run 4-wide (a block with a collapsed one, rare, runs the scalar pass).
PS_TARGET_CLONES("arch=x86-64-v4", "avx", "default")
void add_shell_membrane_forces(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  int t = begin;
  for (; t + 4 <= end; t += 4) {
    const int* v = &sh.tri[3 * t];
    const double* Bp = &sh.bm[4 * t];
    D4 B[4];
    for (int i = 0; i < 4; ++i) B[i] = D4{Bp[i], Bp[4 + i], Bp[8 + i], Bp[12 + i]};
    const V3 x0 = gather(x, v, 3, 0);
    const V3 d1 = sub(gather(x, v, 3, 1), x0), d2 = sub(gather(x, v, 3, 2), x0);
    V3 a, b;
    for (int r = 0; r < 3; ++r) {
      a.c[r] = d1.c[r] * B[0] + d2.c[r] * B[2];
      b.c[r] = d1.c[r] * B[1] + d2.c[r] * B[3];
    }
    const D4 c00 = dot(a, a), c01 = dot(a, b), c11 = dot(b, b);
    const D4 det = c00 * c11 - c01 * c01;
    if (!all4(det > 1e-12)) {
      for (int l = 0; l < 4; ++l) membrane_force(sh, x, t + l, f);
      continue;
    }
    const D4 mu = D4{sh.mu[t], sh.mu[t + 1], sh.mu[t + 2], sh.mu[t + 3]};
    const D4 lam = D4{sh.lambda[t], sh.lambda[t + 1], sh.lambda[t + 2], sh.lambda[t + 3]};
    const D4 at = D4{sh.area_t[t], sh.area_t[t + 1], sh.area_t[t + 2], sh.area_t[t + 3]};
    const D4 sq = sqrt4(det), tau = sqrt4(c00 + c11 + 2.0 * sq);
    const D4 S00 = (c00 + sq) / tau, S01 = c01 / tau, S11 = (c11 + sq) / tau;
    const D4 detS = S00 * S11 - S01 * S01;
    const D4 i00 = S11 / detS, i01 = -S01 / detS, i11 = S00 / detS;
    const D4 trm = S00 + S11 - 2.0;
    const D4 g00 = 2.0 * mu * (S00 - 1.0) + lam * trm, g01 = 2.0 * mu * S01, g11 = 2.0 * mu * (S11 - 1.0) + lam * trm;
    V3 g1, g2;
    for (int r = 0; r < 3; ++r) {
      const D4 r0 = a.c[r] * i00 + b.c[r] * i01, r1 = a.c[r] * i01 + b.c[r] * i11;  // R = F S^-1
      const D4 pa = at * (r0 * g00 + r1 * g01), pb = at * (r0 * g01 + r1 * g11);
      g1.c[r] = pa * B[0] + pb * B[1];
      g2.c[r] = pa * B[2] + pb * B[3];
    }
    for (int l = 0; l < 4; ++l) {
      const int* w = v + 3 * l;
      double* f0 = f[w[0]].data();
      double* f1 = f[w[1]].data();
      double* f2 = f[w[2]].data();
      for (int r = 0; r < 3; ++r) f1[r] -= g1.c[r][l];
      for (int r = 0; r < 3; ++r) f2[r] -= g2.c[r][l];
      for (int r = 0; r < 3; ++r) f0[r] += g1.c[r][l] + g2.c[r][l];
    }
  }
  for (; t < end; ++t) membrane_force(sh, x, t, f);
}

// Hinges [begin, end) into f, four at a time; a lane whose bend is outside atan2_small's range
// takes std::atan2 for it, as the scalar pass does.
PS_TARGET_CLONES("arch=x86-64-v4", "avx", "default")
void add_shell_hinge_forces(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f) {
  int h = begin;
  for (; h + 4 <= end; h += 4) {
    const int* v = &sh.hinge[4 * h];
    const V3 x0 = gather(x, v, 4, 0), x1 = gather(x, v, 4, 1), x2 = gather(x, v, 4, 2), x3 = gather(x, v, 4, 3);
    // hinge_bend's operations
    const V3 e = sub(x1, x0);
    const V3 n1 = cross(e, sub(x2, x0));
    const V3 n2 = cross(sub(x0, x1), sub(x3, x1));
    const D4 le2 = dot(e, e), le = sqrt4(le2), inv_le2 = 1.0 / le2;
    const D4 ys = dot(cross(n1, n2), e), xs = dot(n1, n2) * le;
    const D4 s2 = -le / dot(n1, n1), s3 = -le / dot(n2, n2);
    const D4 a1 = dot(sub(x2, x0), e) * inv_le2, a2 = dot(sub(x3, x0), e) * inv_le2;
    const double* cs = &sh.rest_cs[2 * h];
    const D4 cos0 = D4{cs[0], cs[2], cs[4], cs[6]}, sin0 = D4{cs[1], cs[3], cs[5], cs[7]};
    const D4 sy = ys * cos0 - xs * sin0, cx = xs * cos0 + ys * sin0;
    // atan2_small in four lanes
    D4 bend = atan_series(sy / cx);
    for (int l = 0; l < 4; ++l)
      if (!atan_series_holds(sy[l], cx[l])) bend[l] = std::atan2(sy[l], cx[l]);
    const D4 c = D4{sh.k_hinge[h], sh.k_hinge[h + 1], sh.k_hinge[h + 2], sh.k_hinge[h + 3]} * bend;  // dE/dtheta [N m]
    V3 g[4];
    for (int r = 0; r < 3; ++r) {
      const D4 u2 = s2 * n1.c[r], u3 = s3 * n2.c[r];
      g[0].c[r] = -(1.0 - a1) * u2 - (1.0 - a2) * u3;
      g[1].c[r] = -a1 * u2 - a2 * u3;
      g[2].c[r] = u2;
      g[3].c[r] = u3;
    }
    for (int l = 0; l < 4; ++l)
      for (int i = 0; i < 4; ++i) {
        double* fi = f[v[4 * l + i]].data();
        for (int r = 0; r < 3; ++r) fi[r] -= c[l] * g[i].c[r][l];
      }
  }
  for (; h < end; ++h) hinge_force(sh, x, h, f);
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
