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
inline double atan2_small(double s, double c) {
  if (!(c > 0.0 && std::abs(s) <= 0.25 * c)) return std::atan2(s, c);
  const double z = s / c, w = z * z, w2 = w * w, w4 = w2 * w2, w8 = w4 * w4;
  // a_k = (-1)^k / (2k + 1), as constants (a division by 3.0 would be a division instruction)
  constexpr double a1 = 1.0 / 3, a2 = 1.0 / 5, a3 = 1.0 / 7, a4 = 1.0 / 9, a5 = 1.0 / 11, a6 = 1.0 / 13, a7 = 1.0 / 15;
  constexpr double a8 = 1.0 / 17, a9 = 1.0 / 19, a10 = 1.0 / 21, a11 = 1.0 / 23, a12 = 1.0 / 25;
  const double q0 = 1.0 - w * a1, q1 = a2 - w * a3, q2 = a4 - w * a5, q3 = a6 - w * a7;
  const double q4 = a8 - w * a9, q5 = a10 - w * a11, q6 = a12;
  const double r0 = q0 + q1 * w2, r1 = q2 + q3 * w2, r2 = q4 + q5 * w2;
  const double p = (r0 + r1 * w4) + (r2 + q6 * w4) * w8;
  return z * p;
}

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

void add_shell_elastic_forces(const Model& m, State& s) {
  const ShellElements& sh = m.shells;
  const Vec3* x = s.x.data();
  Vec3* f = s.f.data();
  for (int t = 0, nt = sh.triangle_count(); t < nt; ++t) {
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
  for (int h = 0, nh = sh.hinge_count(); h < nh; ++h) {
    const int* v = &sh.hinge[4 * h];
    Vec3 g[4];
    const double bend = hinge_bend(x[v[0]], x[v[1]], x[v[2]], x[v[3]], sh.rest_cs[2 * h], sh.rest_cs[2 * h + 1], g);
    const double c = sh.k_hinge[h] * bend;  // dE/dtheta [N m]
    for (int i = 0; i < 4; ++i) f[v[i]] -= c * g[i];
  }
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
