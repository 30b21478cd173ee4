#include "app/checks/validation.h"

#include <cmath>

#include "app/checks/validate_dosimetry.h"
#include "app/checks/validate_indentation.h"
#include "app/checks/validate_needle.h"
#include "app/checks/validate_probe.h"

namespace ps::app {

bool ValidationRow::pass() const {
  if (std::isnan(reference)) return std::isfinite(value);
  return std::isfinite(value) && std::abs(value - reference) <= tolerance;
}

const std::vector<ValidationCase>& validation_cases() {
  static const std::vector<ValidationCase> cases = [] {
    std::vector<ValidationCase> all;
    for (auto&& c : tissue_validation_cases()) all.push_back(std::move(c));
    for (auto&& c : needle_validation_cases()) all.push_back(std::move(c));
    for (auto&& c : probe_validation_cases()) all.push_back(std::move(c));
    for (auto&& c : indentation_validation_cases()) all.push_back(std::move(c));
    for (auto&& c : dosimetry_validation_cases()) all.push_back(std::move(c));
    return all;
  }();
  return cases;
}

}  // namespace ps::app
