// Reader for the scenario's filling: section (called by parse_yaml.cpp; internal to the engine
// library). Keys and units:
// filling:
//   max_rate_ml_s: 5           # physiological limit (default 5 ml/s; see engine/tools/filling/filling.h)
//   schedule:                  # each entry exactly one of rate_ml_s, target_ml, target_factor
//     - {component: bladder, target_factor: 2, ramp_s: [0.1, 1.0]}
//     - {component: rectum, rate_ml_s: 1, ramp_s: [0, 2]}
#pragma once
#include "engine/spec/scenario_spec.h"
#include "engine/spec/yaml_reader.h"

namespace ps {

void parse_filling_section(const YamlReader& r, const YAML::Node& node, ScenarioSpec& spec);

}  // namespace ps
