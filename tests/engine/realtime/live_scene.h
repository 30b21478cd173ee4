// A small live scene for the realtime tests: the probe and filling test scene
// (config/validation/probe_pelvis_box.yaml) plus two needles that enter the prostate box from
// its sides (one with an armed biopsy gun, one carrying two seeds), and a script that drives
// every instrument within 0.6 s. Small enough (6-8 mm spacing, 1 substep) for tests that run the
// scene several times.
#pragma once
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/realtime/script.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"

namespace ps::test {

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string live_scene_yaml() {
  std::string y = read_text(std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml");
  const auto p = y.find("name: probe_pelvis_box");
  if (p != std::string::npos) y.replace(p, 22, "name: live_box");
  y += R"(
needles:
  puncture_n: {prostate: 1.0}
  instruments:
    - name: gun
      preset: biopsy_18g
      start_mm: [-30, 26, 0]
      direction: [1, 0, 0]
      gun: {stroke_mm: 10}
    - name: seeder
      preset: brachy_18g
      start_mm: [30, 26, -6]
      direction: [-1, 0, 0]
      seeds_mm: [26, 22]
)";
  return y;
}

inline const char* live_script_yaml() {
  return R"(scenario: live_box
duration_s: 0.6
timeline:
  - {t: 0.0, probe: {insertion_mm: 52, tilt_deg: 2}, over_s: 0.1}
  - {t: 0.02, fill_rate: bladder, ml_s: 100}
  - {t: 0.05, needle: gun, depth_mm: 0}
  - {t: 0.05, needle: seeder, depth_mm: 0}
  - {t: 0.25, needle: gun, depth_mm: 22}
  - {t: 0.30, needle: seeder, depth_mm: 30}
  - {t: 0.30, fire: gun}
  - {t: 0.32, rotate: seeder, angle_deg: 90}
  - {t: 0.35, needle: gun, depth_mm: 22}
  - {t: 0.36, deposit_seed: seeder}
  - {t: 0.40, advance: seeder, speed_mm_s: -80}
  - {t: 0.55, needle: gun, depth_mm: 5}
  - {t: 0.55, select: seeder}
)";
}

// Writes the scene to a file (CLI tests need one) and returns its path.
inline std::string write_live_scene(const std::string& dir) {
  const std::string path = dir + "/live_box.yaml";
  std::ofstream(path) << live_scene_yaml();
  return path;
}

inline Scene make_live_scene() { return build_scene(parse_scenario_text(live_scene_yaml(), "live_box.yaml")); }

}  // namespace ps::test
