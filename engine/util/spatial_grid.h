// Uniform hash grid over points for radius queries at compile time (not used in the step).
#pragma once
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

class SpatialGrid {
 public:
  SpatialGrid(const std::vector<Vec3>& pts, double cell) : pts_(pts), cell_(cell) {
    for (size_t i = 0; i < pts.size(); ++i) cells_[key(cell_of(pts[i]))].push_back(static_cast<int>(i));
  }
  // Calls fn(index, distance) for every point within radius r of q (r <= a few cells).
  template <class Fn>
  void for_each_within(const Vec3& q, double r, Fn&& fn) const {
    const Eigen::Vector3i lo = cell_of(q - Vec3::Constant(r)), hi = cell_of(q + Vec3::Constant(r));
    for (int i = lo[0]; i <= hi[0]; ++i)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int k = lo[2]; k <= hi[2]; ++k) {
          auto it = cells_.find(key(Eigen::Vector3i(i, j, k)));
          if (it == cells_.end()) continue;
          for (int p : it->second) {
            const double d = (pts_[p] - q).norm();
            if (d <= r) fn(p, d);
          }
        }
  }

 private:
  Eigen::Vector3i cell_of(const Vec3& p) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(p[0] / cell_)), static_cast<int>(std::floor(p[1] / cell_)),
                           static_cast<int>(std::floor(p[2] / cell_)));
  }
  static int64_t key(const Eigen::Vector3i& c) {
    return (static_cast<int64_t>(c[0] & 0x1FFFFF) << 42) | (static_cast<int64_t>(c[1] & 0x1FFFFF) << 21) |
           static_cast<int64_t>(c[2] & 0x1FFFFF);
  }
  const std::vector<Vec3>& pts_;
  double cell_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
};

}  // namespace ps
