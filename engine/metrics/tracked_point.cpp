#include "engine/metrics/tracked_point.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ps {

int component_holding(const Model& m, const Vec3& X) {
  int best = -1;
  double best_d2 = INFINITY;
  for (int p = 0; p < m.particle_count(); ++p) {
    if (m.components[m.component_of[p]].kind == ComponentKind::Rigid) continue;
    const double d2 = (m.rest_pos[p] - X).squaredNorm();
    if (d2 < best_d2) { best_d2 = d2; best = p; }
  }
  if (best < 0) return -1;
  const Component& c = m.components[m.component_of[best]];
  return std::sqrt(best_d2) <= 0.75 * c.spacing ? m.component_of[best] : -1;
}

TrackedPoint track_point(const Model& m, const Vec3& X) {
  TrackedPoint t;
  t.rest = X;
  t.component = component_holding(m, X);
  if (t.component < 0) return t;
  const Component& c = m.components[t.component];
  std::vector<std::pair<double, int>> near;
  near.reserve(c.particle_count);
  for (int p = c.first_particle; p < c.first_particle + c.particle_count; ++p) near.emplace_back((m.rest_pos[p] - X).squaredNorm(), p);
  const int k = std::min<int>(kAnchorMaxNeighbours, static_cast<int>(near.size()));
  std::partial_sort(near.begin(), near.begin() + k, near.end());
  int ids[kAnchorMaxNeighbours];
  for (int i = 0; i < k; ++i) ids[i] = near[i].second;
  t.anchor.build(X, ids, k, m.rest_pos, X);
  return t;
}

double winding_number(const Surface& surf, const std::vector<Vec3>& x, const Vec3& p) {
  // van Oosterom & Strackee solid angle of each triangle seen from p
  double omega = 0.0;
  for (const auto& f : surf.faces) {
    const Vec3 a = x[f[0]] - p, b = x[f[1]] - p, c = x[f[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    omega += 2.0 * std::atan2(num, den);
  }
  return omega / (4.0 * std::numbers::pi);
}

}  // namespace ps
