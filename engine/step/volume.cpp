// Exact volume preservation (paper §3.3). For a closed triangulated surface,
//   X1 = X' + lambda * G,   G = masked grad V(X'),   V(X1) = V_target,
// and 6 V(X' + lambda G) = c0 + c1 lambda + c2 lambda^2 + c3 lambda^3 exactly (each face adds
// det[a + lambda ga, b + lambda gb, c + lambda gc]). We take the real root nearest 0 by Newton
// from the linearised guess, iterated to round-off: V matches the target to ~1e-15 relative.
// Coordinates held by fixed/imposed constraints, rigid bodies or contacts get no correction.
// Cost: c0 and the gradient come out of one pass over the faces, c1 = |G|^2 out of the pass
// over the vertices, and a second face pass forms c2 and c3 (3 cross products per face).
#include <cmath>

#include "engine/step/stages.h"
#include "engine/util/multiversion.h"

namespace ps {

double surface_volume(const Surface& surf, const std::vector<Vec3>& x) {
  double v6 = 0.0;
  for (const auto& f : surf.faces) v6 += x[f[0]].dot(x[f[1]].cross(x[f[2]]));
  return v6 / 6.0;
}

// Built twice like the shape-memory stage (shape_memory.cpp): VEX-encoded on CPUs with AVX, the
// same operations otherwise; "avx" has no FMA, so both builds give bit-identical results.
PS_TARGET_CLONES("avx", "default")
bool project_volumes(const Model& m, State& s) {
  Vec3* g = s.volume_grad.data();
  const Vec3* x = s.x.data();
  const uint8_t* locked = m.locked_axes.data();
  const uint8_t* contact = s.contact.data();
  for (size_t si = 0; si < m.surfaces.size(); ++si) {
    const Surface& surf = m.surfaces[si];
    if (!surf.volume_constrained) continue;
    // gradient of 6V with respect to each vertex: sum over incident faces of (b x c); the same
    // pass sums c0 = 6V = sum a.(b x c)
    for (int p : surf.vertices) g[p].setZero();
    double c0 = 0;
    for (const auto& f : surf.faces) {
      const Vec3 &a = x[f[0]], &b = x[f[1]], &c = x[f[2]];
      const Vec3 bc = b.cross(c);
      c0 += a.dot(bc);
      g[f[0]] += bc;
      g[f[1]] += c.cross(a);
      g[f[2]] += a.cross(b);
    }
    // masked gradient G; c1 = sum over faces of the three det terms linear in G
    //    = sum_v G_v . grad_v(6V) = sum_v |G_v|^2 (G is grad 6V with some coordinates zeroed)
    double c1 = 0;
    for (int p : surf.vertices) {
      const uint8_t mask = locked[p] | contact[p];
      if (mask)
        for (int a = 0; a < 3; ++a)
          if (mask & (1u << a)) g[p][a] = 0.0;
      c1 += g[p].squaredNorm();
    }
    // c2 = sum det(Ga,Gb,c) + det(Ga,b,Gc) + det(a,Gb,Gc) = a.(Gb x Gc) + b.(Gc x Ga) + c.(Ga x Gb),
    // c3 = sum det(Ga,Gb,Gc) = Ga.(Gb x Gc)
    double c2 = 0, c3 = 0;
    for (const auto& f : surf.faces) {
      const Vec3 &a = x[f[0]], &b = x[f[1]], &c = x[f[2]];
      const Vec3 &ga = g[f[0]], &gb = g[f[1]], &gc = g[f[2]];
      const Vec3 gbc = gb.cross(gc);
      c2 += a.dot(gbc) + b.dot(gc.cross(ga)) + c.dot(ga.cross(gb));
      c3 += ga.dot(gbc);
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
