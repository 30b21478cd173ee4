#include "engine/model/shell_elements.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "engine/util/error.h"

namespace ps {

double hinge_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, Vec3* grad) {
  const Vec3 e = x1 - x0;
  const Vec3 n1 = e.cross(x2 - x0);         // face (x0, x1, x2), |n1| = 2 A1
  const Vec3 n2 = (x0 - x1).cross(x3 - x1);  // face (x1, x0, x3), |n2| = 2 A2
  const double le2 = e.squaredNorm(), le = std::sqrt(le2);
  const double theta = std::atan2(n1.cross(n2).dot(e) / le, n1.dot(n2));
  if (grad) {
    // d theta / d x2 = -|e| n1 / |n1|^2 (the height of x2 over the edge is |n1| / |e|), the same
    // for x3 with n2; the edge vertices take minus these in proportion to where the opposite
    // vertices project on the edge (translation invariance: the four sum to zero)
    const Vec3 u2 = -le / n1.squaredNorm() * n1;
    const Vec3 u3 = -le / n2.squaredNorm() * n2;
    const double a1 = (x2 - x0).dot(e) / le2, a2 = (x3 - x0).dot(e) / le2;
    grad[0] = -(1.0 - a1) * u2 - (1.0 - a2) * u3;
    grad[1] = -a1 * u2 - a2 * u3;
    grad[2] = u2;
    grad[3] = u3;
  }
  return theta;
}

void build_shell_elements(Model& m, const std::vector<ShellParticle>& mat) {
  ShellElements& sh = m.shells;
  sh = ShellElements{};
  for (const Surface& surf : m.surfaces) {
    const Component& comp = m.components[surf.component];
    if (comp.particle_count == 0 || !(mat[comp.first_particle].mu > 0.0)) continue;
    std::vector<double> face_area(surf.faces.size());
    for (size_t fi = 0; fi < surf.faces.size(); ++fi) {
      const auto& f = surf.faces[fi];
      const Vec3 X0 = m.rest_pos[f[0]], X1 = m.rest_pos[f[1]], X2 = m.rest_pos[f[2]];
      const Vec3 n = (X1 - X0).cross(X2 - X0);
      const double area = 0.5 * n.norm();
      if (!(area > 0.0))
        throw CompileError("component '" + comp.name + "': shell face (" + std::to_string(f[0]) + ", " +
                           std::to_string(f[1]) + ", " + std::to_string(f[2]) + ") has zero area");
      face_area[fi] = area;
      // the face's own orthonormal frame: u along the first edge, w = n x u in the plane
      const Vec3 u = (X1 - X0).normalized(), w = n.normalized().cross(u);
      const double d00 = (X1 - X0).dot(u), d10 = (X1 - X0).dot(w);  // Dm = [[d00, d01], [d10, d11]]
      const double d01 = (X2 - X0).dot(u), d11 = (X2 - X0).dot(w);
      const double det = d00 * d11 - d01 * d10;
      double mu = 0.0, nu = 0.0, t = 0.0;
      for (int i : f) { mu += mat[i].mu / 3.0; nu += mat[i].poisson / 3.0; t += mat[i].thickness / 3.0; }
      sh.tri.insert(sh.tri.end(), {f[0], f[1], f[2]});
      sh.bm.insert(sh.bm.end(), {d11 / det, -d01 / det, -d10 / det, d00 / det});
      sh.area_t.push_back(area * t);
      sh.mu.push_back(mu);
      sh.lambda.push_back(2.0 * mu * nu / (1.0 - nu));  // plane stress: 2 mu lambda / (lambda + 2 mu)
    }
    // hinges: each undirected edge and its two faces; the face where the edge runs a -> b
    // supplies the opposite vertex v[2], the other face v[3]
    std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edge_faces;  // (min, max) -> (face, opposite)
    for (size_t fi = 0; fi < surf.faces.size(); ++fi) {
      const auto& f = surf.faces[fi];
      for (int k = 0; k < 3; ++k) {
        const int a = f[k], b = f[(k + 1) % 3], o = f[(k + 2) % 3];
        edge_faces[{std::min(a, b), std::max(a, b)}].push_back({static_cast<int>(fi), o});
      }
    }
    for (const auto& [edge, faces] : edge_faces) {
      if (faces.size() > 2)
        throw CompileError("component '" + comp.name + "': surface edge (" + std::to_string(edge.first) + ", " +
                           std::to_string(edge.second) + ") is shared by " + std::to_string(faces.size()) +
                           " faces; a shell needs a manifold surface");
      if (faces.size() < 2) continue;  // an open boundary edge has no hinge
      // orient: in faces[0] the edge runs a -> b with its opposite vertex following b
      const auto& f0 = surf.faces[faces[0].first];
      int a = -1, b = -1;
      for (int k = 0; k < 3; ++k)
        if (f0[(k + 2) % 3] == faces[0].second) { a = f0[k]; b = f0[(k + 1) % 3]; }
      const int o0 = faces[0].second, o1 = faces[1].second;
      const double th0 = hinge_angle(m.rest_pos[a], m.rest_pos[b], m.rest_pos[o0], m.rest_pos[o1]);
      double E = 0.0, nu = 0.0, t = 0.0;
      for (int i : {a, b}) {
        E += 0.5 * 2.0 * mat[i].mu * (1.0 + mat[i].poisson);
        nu += 0.5 * mat[i].poisson;
        t += 0.5 * mat[i].thickness;
      }
      const double D = E * t * t * t / (12.0 * (1.0 - nu * nu));  // flexural rigidity [N m]
      const double le2 = (m.rest_pos[b] - m.rest_pos[a]).squaredNorm();
      // 1/2 k_h theta^2 summed over a regular triangulation bent to curvature kappa gives the
      // plate's 1/2 D kappa^2 per area with k_h = 2 D |e|^2 / (A1 + A2) (docs/model.md)
      sh.hinge.insert(sh.hinge.end(), {a, b, o0, o1});
      sh.theta0.push_back(th0);
      sh.rest_cs.insert(sh.rest_cs.end(), {std::cos(th0), std::sin(th0)});
      sh.k_hinge.push_back(2.0 * D * le2 / (face_area[faces[0].first] + face_area[faces[1].first]));
    }
  }
}

}  // namespace ps
