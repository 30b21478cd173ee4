// Prostate zones for biopsy core naming and per-region reporting: level (apex / mid / base by
// thirds of the craniocaudal extent), side (patient right / left of the mid-sagittal plane),
// medial / lateral, and a simplified McNeal zone (peripheral = posterior shell, anterior =
// anterior shell (fibromuscular stroma), transition = the central gland inside both).
//
// Works on any prostate geometry given as a frame (bounding box) plus the depth of the point
// below the capsule, so it applies to the default anatomy and to imported meshes alike. Frame:
// patient RAS (x -> right, y -> anterior, z -> superior), metres.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/util/vec.h"

namespace ps::anatomy {

enum class ProstateLevel : uint8_t { Apex, Mid, Base };
enum class ProstateSide : uint8_t { Right, Left };
enum class ProstateZone : uint8_t { Peripheral, Transition, Anterior };

struct ProstateFrame {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();   // bounding box of the gland [m]
  double peripheral_depth = 8e-3;   // thickness of the peripheral / anterior shells [m]
  Vec3 centre() const { return 0.5 * (lo + hi); }
  // Bounding box of `points` (e.g. the prostate's rest positions).
  static ProstateFrame from_points(const std::vector<Vec3>& points, double peripheral_depth = 8e-3);
};

struct ProstateZoneTag {
  ProstateLevel level = ProstateLevel::Mid;
  ProstateSide side = ProstateSide::Right;
  bool lateral = false;             // farther than half the half-width from the midline
  ProstateZone zone = ProstateZone::Transition;
};

// Classifies point p (inside the gland) at depth_below_capsule [m] (0 on the surface).
//  level: z in the lower third of [lo.z, hi.z] -> apex, upper third -> base, else mid;
//  side: x >= centre.x -> right (RAS), else left;
//  lateral: |x - centre.x| > (hi.x - lo.x) / 4;
//  zone: depth <= peripheral_depth and y < centre.y + (hi.y - centre.y) / 2 -> peripheral
//        (the posterior and lateral shell, where ~70 % of cancers arise and biopsies aim);
//        depth <= peripheral_depth anterior of that -> anterior; deeper -> transition.
ProstateZoneTag classify_prostate_point(const Vec3& p, double depth_below_capsule, const ProstateFrame& frame);

// Tag names the compile step attaches to prostate particles (Model::tag_names), in this order.
inline constexpr std::array<const char*, 10> kZoneTagNames = {
    "apex", "mid", "base", "right", "left", "medial", "lateral", "peripheral", "transition", "anterior"};

// The kZoneTagNames indices that describe `tag` (four: level, side, medial/lateral, zone).
std::array<int, 4> zone_tag_indices(const ProstateZoneTag& tag);

// Biopsy core name in the usual 12-core scheme, e.g. "right base lateral" (level, side and
// medial/lateral), followed by the zone: "right base lateral (peripheral)".
std::string zone_label(const ProstateZoneTag& tag);

}  // namespace ps::anatomy
