// Range checks for numeric command-line options, with a message a user can act on.
// CLI11's PositiveNumber had no upper bound and printed it as the full decimal expansion of
// DBL_MAX; without a bound, `--duration 1e300` overflowed the tick count and a run "succeeded"
// with 0 steps, and `--factor 1e-300` ran forever. The simulated-time bound is the scenario's
// own (ScenarioSpec::kMaxDuration, also `time.duration_s`'s), so a command line cannot ask for
// more than a scenario file may.
#pragma once
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "engine/spec/scenario_spec.h"

namespace ps::app {

// Accepts a finite number in [lo, hi] (lo excluded when lo_open); the error names the bounds
// with their unit, e.g. "must be in (0, 1e+06] s, got 1e+300".
inline CLI::Validator in_range(double lo, double hi, const std::string& unit, bool lo_open = false) {
  char desc[96];
  std::snprintf(desc, sizeof desc, "%s%g, %g]%s%s", lo_open ? "(" : "[", lo, hi, unit.empty() ? "" : " ", unit.c_str());
  const std::string bounds = desc;
  return CLI::Validator(
      [lo, hi, lo_open, bounds](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return "expected a number, got '" + text + "'";
        const bool above_lo = lo_open ? v > lo : v >= lo;
        if (std::isfinite(v) && above_lo && v <= hi) return {};
        return "must be in " + bounds + ", got " + text;
      },
      "in " + bounds);
}

// Simulated time of a run [s]: the range of a scenario's time.duration_s.
inline CLI::Validator simulated_seconds() { return in_range(0.0, ScenarioSpec::kMaxDuration, "s", true); }

}  // namespace ps::app
