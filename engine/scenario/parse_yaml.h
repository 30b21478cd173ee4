// Reads a scenario YAML file into a ScenarioSpec (units converted to SI here, once).
// Every problem is an InputError naming file:line and the key: missing or unknown keys, wrong
// types, negative moduli or spacings, unknown materials, unreadable files.
#pragma once
#include <string>

#include "engine/spec/scenario_spec.h"

namespace ps {

ScenarioSpec parse_scenario_file(const std::string& path);
// Same, from text; `path` is used in messages and to resolve relative mesh paths.
ScenarioSpec parse_scenario_text(const std::string& text, const std::string& path);

}  // namespace ps
