#include "engine/dosimetry/dose_grid.h"

#include <algorithm>
#include <cmath>

#include "engine/dosimetry/tg43.h"

namespace ps::dosimetry {

GridSpec grid_around(const Vec3& lo_mm, const Vec3& hi_mm, double margin_mm, double spacing_mm) {
  GridSpec g;
  g.spacing_mm = spacing_mm;
  const Vec3 lo = lo_mm - Vec3::Constant(margin_mm), hi = hi_mm + Vec3::Constant(margin_mm);
  g.origin_mm = lo + Vec3::Constant(0.5 * spacing_mm);
  g.nx = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / spacing_mm)));
  g.ny = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / spacing_mm)));
  g.nz = std::max(1, static_cast<int>(std::ceil((hi.z() - lo.z()) / spacing_mm)));
  return g;
}

DoseKernel::DoseKernel(const SourceModel& s, double extent_mm, double step_mm)
    : model_(&s), step_mm_(step_mm), inv_step_(1.0 / step_mm), n_(static_cast<int>(extent_mm / step_mm) + 2) {
  k_.resize(static_cast<size_t>(n_) * n_);
  const double f = permanent_dose_factor(s);
  for (int ia = 0; ia < n_; ++ia)
    for (int ir = 0; ir < n_; ++ir) {
      const double z = ia * step_mm, rho = ir * step_mm;
      const double r_cm = 0.1 * std::hypot(z, rho);
      k_[static_cast<size_t>(ia) * n_ + ir] = static_cast<float>(dose_rate_per_u(s, r_cm, std::atan2(rho, z)) * f);
    }
}

double DoseKernel::gy_per_u(double along_abs_mm, double away_mm) const {
  const double a = along_abs_mm * inv_step_, r = away_mm * inv_step_;
  if (a >= n_ - 1 || r >= n_ - 1) {  // beyond the table: the formalism itself
    const double r_cm = 0.1 * std::hypot(along_abs_mm, away_mm);
    return dose_rate_per_u(*model_, r_cm, std::atan2(away_mm, along_abs_mm)) * permanent_dose_factor(*model_);
  }
  const int ia = static_cast<int>(a), ir = static_cast<int>(r);
  const double u = a - ia, v = r - ir;
  const float* p = &k_[static_cast<size_t>(ia) * n_ + ir];
  return (1 - u) * ((1 - v) * p[0] + v * p[1]) + u * ((1 - v) * p[n_] + v * p[n_ + 1]);
}

DoseAccumulator::DoseAccumulator(const SourceModel& s, const GridSpec& g) : spec_(g), kernel_(s), dose_(g.size(), 0.0f) {}

void DoseAccumulator::add(const Seed& s, float sign) {
  const GridSpec& g = spec_;
  const double sk = sign * s.strength_u;
  const Vec3 a = s.axis;
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j) {
      const Vec3 row = g.centre_mm(0, j, k) - s.centre_mm;
      float* out = &dose_[g.index(0, j, k)];
      const double a0 = row.dot(a), r0 = row.squaredNorm();
      const double ax = a.x() * g.spacing_mm;
      for (int i = 0; i < g.nx; ++i) {
        const double dx = i * g.spacing_mm;
        const double along = a0 + i * ax;
        const double r2 = r0 + 2.0 * row.x() * dx + dx * dx;
        const double away = std::sqrt(std::max(0.0, r2 - along * along));
        out[i] += static_cast<float>(sk * kernel_.gy_per_u(std::abs(along), away));
      }
    }
}

int DoseAccumulator::update(const std::vector<Seed>& seeds, double move_tol_mm, int max_moved) {
  int passes = 0, moved = 0;
  lagging_ = 0;
  while (applied_.size() > seeds.size()) {
    add(applied_.back(), -1.0f);
    applied_.pop_back();
    ++passes;
  }
  const double cos_tol = std::cos(3.0 * 3.141592653589793 / 180.0);
  for (size_t i = 0; i < seeds.size(); ++i) {
    if (i < applied_.size()) {
      const Seed& o = applied_[i];
      if ((o.centre_mm - seeds[i].centre_mm).norm() <= move_tol_mm && o.axis.dot(seeds[i].axis) >= cos_tol &&
          o.strength_u == seeds[i].strength_u)
        continue;
      if (moved >= max_moved) {
        ++lagging_;
        continue;
      }
      ++moved;
      add(o, -1.0f);
      add(seeds[i], 1.0f);
      applied_[i] = seeds[i];
      passes += 2;
    } else {
      add(seeds[i], 1.0f);
      applied_.push_back(seeds[i]);
      ++passes;
    }
  }
  return passes;
}

void DoseAccumulator::rebuild(const std::vector<Seed>& seeds) {
  std::fill(dose_.begin(), dose_.end(), 0.0f);
  applied_.clear();
  lagging_ = 0;
  for (const Seed& s : seeds) {
    add(s, 1.0f);
    applied_.push_back(s);
  }
}

}  // namespace ps::dosimetry
