// Validation cases for `prostatesim validate`: each compares the simulator with a reference no
// one here wrote (measured phantom data, analytic solutions, published curves, an independent
// FEM solver) and returns rows of (case, metric, value, reference, unit) with a tolerance.
// Cases live in app/checks/validate_*.cpp and are listed in validation_cases() (validation.cpp).
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace ps::app {

struct ValidationRow {
  std::string case_name;
  std::string metric;
  double value = 0.0;
  double reference = 0.0;        // NaN when the metric is reported without a reference
  std::string unit;
  double tolerance = 0.0;        // pass when |value - reference| <= tolerance (NaN ref: always)
  bool pass() const;
};

struct ValidationCase {
  std::string name;
  std::string description;
  // Runs the case; `source_dir` is the repository root (scenarios in config/validation/),
  // `shared_data` the folder ../shared/data beside it.
  std::function<std::vector<ValidationRow>(const std::string& source_dir, const std::string& shared_data)> run;
  // Writes per-particle files under `validate --out` (checked before any case runs).
  bool writes_files = false;
};

const std::vector<ValidationCase>& validation_cases();

// per-file registration functions (one per validate_*.cpp), collected by validation_cases()
std::vector<ValidationCase> tissue_validation_cases();   // validate_tissue.cpp

}  // namespace ps::app
