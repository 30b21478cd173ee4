#include "engine/dosimetry/organ_mask.h"

#include <algorithm>
#include <cmath>

namespace ps::dosimetry {

void fill_closed_surface(const GridSpec& g, const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& faces,
                         uint8_t bit, std::vector<uint8_t>& mask) {
  mask.resize(g.size(), 0);
  // crossings per (j, k) row: x of each triangle the row's line passes through
  std::vector<std::vector<double>> rows(static_cast<size_t>(g.ny) * g.nz);
  const double h = g.spacing_mm;
  for (const auto& f : faces) {
    const Vec3 &a = v[f[0]], &b = v[f[1]], &c = v[f[2]];
    const double ymin = std::min({a.y(), b.y(), c.y()}), ymax = std::max({a.y(), b.y(), c.y()});
    const double zmin = std::min({a.z(), b.z(), c.z()}), zmax = std::max({a.z(), b.z(), c.z()});
    const int j0 = std::max(0, static_cast<int>(std::ceil((ymin - g.origin_mm.y()) / h)));
    const int j1 = std::min(g.ny - 1, static_cast<int>(std::floor((ymax - g.origin_mm.y()) / h)));
    const int k0 = std::max(0, static_cast<int>(std::ceil((zmin - g.origin_mm.z()) / h)));
    const int k1 = std::min(g.nz - 1, static_cast<int>(std::floor((zmax - g.origin_mm.z()) / h)));
    // barycentric in the (y, z) projection
    const double d = (b.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (b.z() - a.z());
    if (std::abs(d) < 1e-12) continue;  // edge-on to the rows: crossed by none of them
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j) {
        // a tiny offset keeps rows off the shared edges and vertices (each crossing counted once)
        const double py = g.origin_mm.y() + j * h + 1.3e-7, pz = g.origin_mm.z() + k * h + 0.7e-7;
        const double l1 = ((py - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (pz - a.z())) / d;
        const double l2 = ((b.y() - a.y()) * (pz - a.z()) - (py - a.y()) * (b.z() - a.z())) / d;
        if (l1 < 0 || l2 < 0 || l1 + l2 > 1) continue;
        rows[static_cast<size_t>(k) * g.ny + j].push_back(a.x() + l1 * (b.x() - a.x()) + l2 * (c.x() - a.x()));
      }
  }
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j) {
      std::vector<double>& xs = rows[static_cast<size_t>(k) * g.ny + j];
      if (xs.size() < 2) continue;
      std::sort(xs.begin(), xs.end());
      for (size_t q = 0; q + 1 < xs.size(); q += 2) {
        const int i0 = std::max(0, static_cast<int>(std::ceil((xs[q] - g.origin_mm.x()) / h)));
        const int i1 = std::min(g.nx - 1, static_cast<int>(std::floor((xs[q + 1] - g.origin_mm.x()) / h)));
        for (int i = i0; i <= i1; ++i) mask[g.index(i, j, k)] |= bit;
      }
    }
}

void fill_tube(const GridSpec& g, const std::vector<Vec3>& line, double radius_mm, uint8_t bit, std::vector<uint8_t>& mask) {
  mask.resize(g.size(), 0);
  const double h = g.spacing_mm, r2 = radius_mm * radius_mm;
  for (size_t s = 0; s + 1 < line.size(); ++s) {
    const Vec3 a = line[s], b = line[s + 1], ab = b - a;
    const double L2 = std::max(ab.squaredNorm(), 1e-12);
    const Vec3 lo = a.cwiseMin(b) - Vec3::Constant(radius_mm), hi = a.cwiseMax(b) + Vec3::Constant(radius_mm);
    const int i0 = std::max(0, static_cast<int>(std::ceil((lo.x() - g.origin_mm.x()) / h)));
    const int i1 = std::min(g.nx - 1, static_cast<int>(std::floor((hi.x() - g.origin_mm.x()) / h)));
    const int j0 = std::max(0, static_cast<int>(std::ceil((lo.y() - g.origin_mm.y()) / h)));
    const int j1 = std::min(g.ny - 1, static_cast<int>(std::floor((hi.y() - g.origin_mm.y()) / h)));
    const int k0 = std::max(0, static_cast<int>(std::ceil((lo.z() - g.origin_mm.z()) / h)));
    const int k1 = std::min(g.nz - 1, static_cast<int>(std::floor((hi.z() - g.origin_mm.z()) / h)));
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const Vec3 p = g.centre_mm(i, j, k);
          const double t = std::clamp((p - a).dot(ab) / L2, 0.0, 1.0);
          if ((p - (a + t * ab)).squaredNorm() <= r2) mask[g.index(i, j, k)] |= bit;
        }
  }
}

void clear_where(std::vector<uint8_t>& mask, uint8_t bit, uint8_t other) {
  for (uint8_t& m : mask)
    if (m & other) m = static_cast<uint8_t>(m & ~bit);
}

}  // namespace ps::dosimetry
