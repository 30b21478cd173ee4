// Small scenario texts shared by engine tests.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/state/state.h"
#include "engine/util/error.h"

namespace ps::test {

// A volumetric elastic cube (side mm, spacing mm), optionally incompressible, bottom fixed.
inline std::string cube_yaml(double side_mm = 40, double spacing_mm = 10, bool incompressible = false,
                             bool fix_bottom = true, double damping = 20, const std::string& gravity = "[0, 0, -9.81]") {
  std::string s = "name: test_cube\n"
                  "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
                  "gravity_m_s2: " + gravity + "\n"
                  "materials:\n"
                  "  soft: {young_kpa: 10, density_kg_m3: 1000, damping_1_s: " + std::to_string(damping) +
                  ", incompressible: " + (incompressible ? "true" : "false") + "}\n"
                  "components:\n"
                  "  - name: cube\n"
                  "    material: soft\n"
                  "    spacing_mm: " + std::to_string(spacing_mm) + "\n"
                  "    box: {min_mm: [0, 0, 0], max_mm: [" + std::to_string(side_mm) + ", " + std::to_string(side_mm) + ", " +
                  std::to_string(side_mm) + "]}\n";
  if (fix_bottom) s += "constraints:\n  - fix: {component: cube, region: {box: {min_mm: [-1, -1, -1], max_mm: [1000, 1000, 0.5]}}}\n";
  return s;
}

inline std::shared_ptr<const Model> compile_text(const std::string& yaml) {
  return compile_scenario(parse_scenario_text(yaml, "test.yaml"));
}

// The scenario text must be refused with an InputError naming `field` at a line (gtest failures
// otherwise).
inline void expect_refused_with_field(const std::string& yaml, const std::string& field) {
  try {
    compile_text(yaml);
    ADD_FAILURE() << "accepted: " << field;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field);
    EXPECT_GT(e.line(), 0);
  }
}

// Central-difference check of a force against an energy: over every stride-th particle of s,
// returns {largest |-(dE/dx) - force|, largest |force|} (the second scales the first) [N].
// `energy(s)` must not change s.x; s.x is restored after each probe.
template <class Energy>
std::pair<double, double> gradient_mismatch(State& s, const std::vector<Vec3>& force, int stride, Energy energy) {
  double worst = 0, scale = 0;
  for (size_t p = 0; p < s.x.size(); p += static_cast<size_t>(stride))
    for (int a = 0; a < 3; ++a) {
      const double h = 1e-7, x0 = s.x[p][a];
      s.x[p][a] = x0 + h;
      const double ep = energy(s);
      s.x[p][a] = x0 - h;
      const double em = energy(s);
      s.x[p][a] = x0;
      worst = std::max(worst, std::abs(-(ep - em) / (2 * h) - force[p][a]));
      scale = std::max(scale, std::abs(force[p][a]));
    }
  return {worst, scale};
}

}  // namespace ps::test
