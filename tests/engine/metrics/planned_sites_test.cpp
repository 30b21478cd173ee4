// The 12 planned sites of the systematic biopsy in the default anatomy: each is peripheral-zone
// tissue of its side, level and medial/lateral half, its centre inside the gland, on its own side,
// the base cranial of the apex and lateral sites farther from the midline than medial ones; and
// the 12-core map's cells name them.
#include "engine/metrics/planned_sites.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "engine/metrics/sextant_map.h"
#include "engine/metrics/tracked_point.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"

namespace ps {
namespace {

TEST(PlannedSites, TwelveCoreSitesOfTheDefaultAnatomy) {
  const ScenarioSpec spec = parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
  const auto m = compile_scenario(spec);
  const std::vector<PlannedSite> sites = planned_sites(*m, twelve_core_sites());
  ASSERT_EQ(sites.size(), 12u);
  const int gland = m->find_component("prostate");
  const Surface& surf = m->surfaces[m->components[gland].surface];
  std::printf("{\"biopsy\": {\"planned_site_centres_mm\": {");
  for (size_t k = 0; k < sites.size(); ++k) {
    const PlannedSite& s = sites[k];
    std::printf("%s\"%s\": [%.3f, %.3f, %.3f]", k ? ", " : "", s.label.c_str(), 1e3 * s.centre.x(), 1e3 * s.centre.y(), 1e3 * s.centre.z());
    EXPECT_GT(s.particles, 0) << s.label;
    EXPECT_GT(winding_number(surf, m->rest_pos, s.centre), 0.5) << s.label << " inside the gland";
    // patient right is +x
    EXPECT_EQ(s.centre.x() > 0, s.label.rfind("right", 0) == 0) << s.label;
    EXPECT_GE(sextant_cell(s.label), 0) << s.label;
  }
  std::printf("}}}\n");
  auto at = [&](const char* l) {
    for (const PlannedSite& s : sites)
      if (s.label == l) return s.centre;
    return Vec3(Vec3::Zero());
  };
  EXPECT_GT(at("right base lateral").z(), at("right apex lateral").z());
  EXPECT_GT(std::abs(at("right mid lateral").x()), std::abs(at("right mid medial").x()));
  EXPECT_GT(std::abs(at("left mid lateral").x()), std::abs(at("left mid medial").x()));
}

}  // namespace
}  // namespace ps
