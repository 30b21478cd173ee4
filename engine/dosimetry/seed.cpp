#include "engine/dosimetry/seed.h"

#include <cmath>

#include "engine/dosimetry/tg43.h"

namespace ps::dosimetry {

double seed_total_dose_gy(const SourceModel& s, const Seed& seed, const Vec3& p_mm) {
  const Vec3 d = p_mm - seed.centre_mm;
  const double along = d.dot(seed.axis);
  const double away = (d - along * seed.axis).norm();
  const double r_cm = 0.1 * d.norm();
  const double theta = std::atan2(away, std::abs(along));
  return seed.strength_u * dose_rate_per_u(s, r_cm, theta) * permanent_dose_factor(s);
}

double total_dose_gy(const SourceModel& s, const std::vector<Seed>& seeds, const Vec3& p_mm) {
  double d = 0.0;
  for (const Seed& q : seeds) d += seed_total_dose_gy(s, q, p_mm);
  return d;
}

}  // namespace ps::dosimetry
