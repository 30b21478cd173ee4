#include "engine/anatomy/zones.h"

#include <cmath>

namespace ps::anatomy {

ProstateFrame ProstateFrame::from_points(const std::vector<Vec3>& points, double peripheral_depth) {
  ProstateFrame f;
  f.peripheral_depth = peripheral_depth;
  if (points.empty()) return f;
  f.lo = f.hi = points.front();
  for (const Vec3& p : points) {
    f.lo = f.lo.cwiseMin(p);
    f.hi = f.hi.cwiseMax(p);
  }
  return f;
}

ProstateZoneTag classify_prostate_point(const Vec3& p, double depth, const ProstateFrame& f) {
  ProstateZoneTag t;
  const Vec3 c = f.centre();
  const double third = (f.hi.z() - f.lo.z()) / 3.0;
  t.level = p.z() < f.lo.z() + third ? ProstateLevel::Apex
            : p.z() > f.hi.z() - third ? ProstateLevel::Base
                                        : ProstateLevel::Mid;
  t.side = p.x() >= c.x() ? ProstateSide::Right : ProstateSide::Left;
  t.lateral = std::abs(p.x() - c.x()) > 0.25 * (f.hi.x() - f.lo.x());
  if (depth > f.peripheral_depth) t.zone = ProstateZone::Transition;
  else if (p.y() < c.y() + 0.5 * (f.hi.y() - c.y())) t.zone = ProstateZone::Peripheral;
  else t.zone = ProstateZone::Anterior;
  return t;
}

std::array<int, 4> zone_tag_indices(const ProstateZoneTag& t) {
  return {static_cast<int>(t.level), 3 + static_cast<int>(t.side), t.lateral ? 6 : 5, 7 + static_cast<int>(t.zone)};
}

std::string zone_label(const ProstateZoneTag& t) {
  const auto i = zone_tag_indices(t);
  return std::string(kZoneTagNames[i[1]]) + " " + kZoneTagNames[i[0]] + " " + kZoneTagNames[i[2]] + " (" +
         kZoneTagNames[i[3]] + ")";
}

}  // namespace ps::anatomy
