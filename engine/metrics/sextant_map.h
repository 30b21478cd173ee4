// The 12-core map a urologist draws on the biopsy form: rows base / mid / apex, columns right
// lateral, right medial, left medial, left lateral (the patient's right on the left, as the form
// is drawn facing the patient); per cell whether it was planned, how many cores were taken there
// and whether one held lesion. Built from a session's cores (SessionReport) or live from the
// window's own list.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "engine/metrics/session_metrics.h"

namespace ps {

struct SextantCell {
  std::string site;                 // "right base lateral"
  bool planned = false;
  int cores = 0;
  bool lesion = false;              // a core here held lesion
};

struct SextantMap {
  std::array<SextantCell, 12> cells;  // row-major: base, mid, apex x right lat, right med, left med, left lat
  int off_map = 0;                    // cores at no 12-core site (outside the gland, or no zone tags)
};

// Cell of a site label ("right mid medial", or a core's "right mid medial (peripheral)"), -1: none.
int sextant_cell(const std::string& site);
SextantMap empty_sextant_map(const std::vector<std::string>& planned_sites);
SextantMap sextant_map(const SessionReport& r);

}  // namespace ps
