// MetricsOptions for a scenario: the gland is the `prostate_zones:` component (else "prostate"),
// and the urethra centre line is read from urethra.csv beside the gland's mesh when the anatomy
// folder has one (assets/anatomy, `prostatesim make-anatomy`). Setup only (reads a file).
#pragma once
#include <string>
#include <vector>

#include "engine/metrics/session_metrics.h"
#include "engine/spec/scenario_spec.h"

namespace ps {

// Parses urethra.csv ("# ..." comments, header x_mm,y_mm,z_mm, rows in mm) into metres;
// InputError naming file:line on a bad row.
std::vector<Vec3> parse_urethra_csv(const std::string& text, const std::string& file);

MetricsOptions metrics_options_for(const ScenarioSpec& spec);

}  // namespace ps
