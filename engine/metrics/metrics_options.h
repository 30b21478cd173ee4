// MetricsOptions for a compiled scenario: the gland is the `prostate_zones:` component (else the
// first component whose role is prostate), the urethra centre line the Model's (read once at
// compile from urethra.csv beside the gland's mesh, engine/scenario/compile_urethra.cpp).
#pragma once
#include <string>
#include <vector>

#include "engine/metrics/session_metrics.h"
#include "engine/spec/scenario_spec.h"

namespace ps {

MetricsOptions metrics_options_for(const ScenarioSpec& spec, const Model& model);

}  // namespace ps
