#include "engine/metrics/sextant_map.h"

namespace ps {

namespace {
constexpr const char* kRows[3] = {"base", "mid", "apex"};
constexpr const char* kCols[4][2] = {{"right", "lateral"}, {"right", "medial"}, {"left", "medial"}, {"left", "lateral"}};
}  // namespace

int sextant_cell(const std::string& site) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      const std::string label = std::string(kCols[c][0]) + " " + kRows[r] + " " + kCols[c][1];
      if (site.rfind(label, 0) == 0) return 4 * r + c;
    }
  return -1;
}

SextantMap empty_sextant_map(const std::vector<std::string>& planned_sites) {
  SextantMap map;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) map.cells[4 * r + c].site = std::string(kCols[c][0]) + " " + kRows[r] + " " + kCols[c][1];
  for (const std::string& p : planned_sites) {
    const int k = sextant_cell(p);
    if (k >= 0) map.cells[k].planned = true;
  }
  return map;
}

SextantMap sextant_map(const SessionReport& r) {
  SextantMap map = empty_sextant_map(r.planned_sites);
  for (const CoreMetrics& c : r.cores) {
    if (!c.taken) continue;
    const int k = sextant_cell(c.site);
    if (k < 0) { ++map.off_map; continue; }
    ++map.cells[k].cores;
    map.cells[k].lesion |= c.lesion_hit;
  }
  return map;
}

}  // namespace ps
