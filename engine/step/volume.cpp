// Exact volume preservation (paper §3.3). For a closed triangulated surface,
//   X1 = X' + lambda * G,   G = masked grad V(X'),   V(X1) = V_target,
// and 6 V(X' + lambda G) = c0 + c1 lambda + c2 lambda^2 + c3 lambda^3 exactly (each face adds
// det[a + lambda ga, b + lambda gb, c + lambda gc]). We take the real root nearest 0 by Newton
// from the linearised guess, iterated to round-off: V matches the target to ~1e-15 relative.
// Coordinates held by fixed/imposed constraints, rigid bodies or contacts get no correction.
#include <cmath>

#include "engine/step/stages.h"

namespace ps {

double surface_volume(const Surface& surf, const std::vector<Vec3>& x) {
  double v6 = 0.0;
  for (const auto& f : surf.faces) v6 += x[f[0]].dot(x[f[1]].cross(x[f[2]]));
  return v6 / 6.0;
}

namespace {
inline double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)); }
}  // namespace

bool project_volumes(const Model& m, State& s) {
  for (size_t si = 0; si < m.surfaces.size(); ++si) {
    const Surface& surf = m.surfaces[si];
    if (!surf.volume_constrained) continue;
    // gradient of 6V with respect to each vertex: sum over incident faces of (b x c)
    Vec3* g = s.volume_grad.data();
    for (int p : surf.vertices) g[p].setZero();
    for (const auto& f : surf.faces) {
      g[f[0]] += s.x[f[1]].cross(s.x[f[2]]);
      g[f[1]] += s.x[f[2]].cross(s.x[f[0]]);
      g[f[2]] += s.x[f[0]].cross(s.x[f[1]]);
    }
    for (int p : surf.vertices) {
      const uint8_t mask = m.locked_axes[p] | s.contact[p];
      for (int a = 0; a < 3; ++a)
        if (mask & (1u << a)) g[p][a] = 0.0;
    }
    double c0 = 0, c1 = 0, c2 = 0, c3 = 0;
    for (const auto& f : surf.faces) {
      const Vec3 &a = s.x[f[0]], &b = s.x[f[1]], &c = s.x[f[2]];
      const Vec3 &ga = g[f[0]], &gb = g[f[1]], &gc = g[f[2]];
      c0 += det3(a, b, c);
      c1 += det3(ga, b, c) + det3(a, gb, c) + det3(a, b, gc);
      c2 += det3(ga, gb, c) + det3(ga, b, gc) + det3(a, gb, gc);
      c3 += det3(ga, gb, gc);
    }
    const double target6 = 6.0 * s.target_volume[si];
    const double r0 = c0 - target6;
    if (r0 == 0.0) { s.last_lambda[si] = 0.0; continue; }
    if (!(c1 > 0.0)) {
      s.fault = StepFault{StepFault::VolumeSolve, surf.vertices.empty() ? -1 : surf.vertices[0], s.time, r0};
      return false;
    }
    // Newton on the cubic from the linearised root; the polynomial is monotone near 0 because
    // c1 = |G|^2 > 0, so this converges to the root nearest 0 for any reasonable deformation.
    double lambda = -r0 / c1;
    for (int it = 0; it < 60; ++it) {
      const double val = r0 + lambda * (c1 + lambda * (c2 + lambda * c3));
      const double der = c1 + lambda * (2.0 * c2 + 3.0 * lambda * c3);
      if (der == 0.0 || !std::isfinite(der)) break;
      const double step = val / der;
      lambda -= step;
      if (std::abs(step) <= 4e-16 * std::abs(lambda)) break;  // at round-off
    }
    const double residual = r0 + lambda * (c1 + lambda * (c2 + lambda * c3));
    const bool converged = std::abs(residual) <= 1e-13 * std::abs(target6);
    if (!converged || !std::isfinite(lambda)) {
      s.fault = StepFault{StepFault::VolumeSolve, surf.vertices.empty() ? -1 : surf.vertices[0], s.time, r0};
      return false;
    }
    for (int p : surf.vertices) s.x[p] += lambda * g[p];
    s.last_lambda[si] = lambda;
  }
  return true;
}

}  // namespace ps
