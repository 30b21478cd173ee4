// Naming a biopsy core the way clinicians name it (issue 3 item 4, issue 4 item 6): from the
// particle tags of what lies in the notch (CoreReport::per_tag, filled from Model::tag_names /
// particle_tags by the needle tool), the 12-core site of the prostate tissue ("right mid medial
// (peripheral)"), every prostate zone the notch crosses, and the lesion / tumour tags it holds.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "engine/tools/needle/needle.h"

namespace ps {

struct CoreSite {
  // Site of the majority of the core's prostate particles in the 12-core scheme plus zone, as
  // anatomy::zone_label gives it: in each group (level, side, medial/lateral, zone) the tag with
  // the most particles (ties: the first of anatomy::kZoneTagNames). Empty when no particle in
  // the notch carries a prostate zone tag (prostate_zones: absent, or the core missed the gland).
  std::string label;
  std::vector<std::pair<std::string, int>> zones;    // every zone tag in the notch, most particles first
  std::vector<std::pair<std::string, int>> lesions;  // the other tags (lesion, tumour...), most first
};

CoreSite core_site(const CoreReport& core);

}  // namespace ps
