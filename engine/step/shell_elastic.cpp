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
    const double th = hinge_angle(x[v[0]], x[v[1]], x[v[2]], x[v[3]], g);
    const double c = sh.k_hinge[h] * wrap_angle(th - sh.theta0[h]);  // dE/dtheta [N m]
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
