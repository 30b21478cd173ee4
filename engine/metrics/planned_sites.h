// The planned sites of a systematic biopsy (NeedleSpec::planned_sites, "right base lateral"...) in
// the compiled model: each site is the peripheral-zone tissue carrying its three zone tags
// (engine/anatomy/zones.h); its centre, the centroid of that tissue in the gland's posterior half
// (the posterior and posterolateral PZ a systematic core aims at), is where an expert aims the notch. Used by the session
// metrics (error of each core to its site), the sextant map and the expert script's check.
#pragma once
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

struct PlannedSite {
  std::string label;                // "right base lateral"
  Vec3 centre = Vec3::Zero();       // centroid at rest of its peripheral-zone particles in the gland's posterior half [m]
  int particles = 0;                // 0: the model has no such tissue (no zone tags)
};

// One entry per label, in order. A label is up to three words of anatomy::kZoneTagNames (side,
// level, medial/lateral); the site's particles carry every one of them and "peripheral".
std::vector<PlannedSite> planned_sites(const Model& m, const std::vector<std::string>& labels);

// Distance from point c to the segment [a, b] [m].
double distance_to_segment(const Vec3& c, const Vec3& a, const Vec3& b);

}  // namespace ps
