// Scenes the benchmarks and the stability study run, built from scenario text so they go through
// the same parser and compiler as a user's file (nothing read from disk).
//   cube N        volumetric N x N x N lattice, 6 mm spacing (the calibration's reference
//                 spacing), E = 10 kPa, bottom layer fixed, gravity -z. N = 11 -> 1331 particles
//                 (the paper's "1300 particles, 133 ms per iteration" size), N = 22 -> 10648.
//   cylinder      the truth-cylinder phantom as a primitive (docs/validation.md): radius 19 mm,
//                 length 178 mm along +z, spacing 6 mm, E = 60 kPa, 1070 kg/m^3, surface mesh +
//                 interior lattice (volumetric_particles, the path a mesh file takes), clamped at
//                 z = 0, gravity -y: 1300 particles. Surface particles have ~8 neighbours, hence
//                 many beta triplets (28 per particle).
//   cube11s       cube 11 with `model: strain` (shape memory + strain memory, docs/model.md);
//                 cube11si incompressible (local nu = 0.49, volume constraint)
// Trailing i in a scene name: incompressible (volume constraint on the surface).
#pragma once
#include <memory>
#include <string>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"

namespace ps::bench {

inline constexpr int kCubeSpacingMm = 6;

inline std::string material_yaml(bool incompressible, double damping_1_s, double young_kpa = 10,
                                 double density_kg_m3 = 1000) {
  return "materials:\n"
         "  soft: {young_kpa: " + std::to_string(young_kpa) + ", density_kg_m3: " + std::to_string(density_kg_m3) +
         ", damping_1_s: " + std::to_string(damping_1_s) + ", incompressible: " + (incompressible ? "true" : "false") +
         "}\n";
}

// points_per_side lattice points on each edge, spacing_mm apart
inline std::string cube_scene(int points_per_side, bool incompressible, double damping_1_s = 20,
                              int spacing_mm = kCubeSpacingMm) {
  const std::string side = std::to_string(spacing_mm * (points_per_side - 1));
  return "name: bench_cube\n"
         "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
         "gravity_m_s2: [0, 0, -9.81]\n" +
         material_yaml(incompressible, damping_1_s) +
         "components:\n"
         "  - name: cube\n"
         "    material: soft\n"
         "    spacing_mm: " + std::to_string(spacing_mm) + "\n"
         "    box: {min_mm: [0, 0, 0], max_mm: [" + side + ", " + side + ", " + side + "]}\n"
         "constraints:\n"
         "  - fix: {component: cube, region: {box: {min_mm: [-1, -1, -1], max_mm: [100000, 100000, 0.5]}}}\n";
}

// cube_scene with the material switched to model: strain (the only difference)
inline std::string strain_cube_scene(int points_per_side, bool incompressible, double damping_1_s = 20) {
  std::string t = cube_scene(points_per_side, incompressible, damping_1_s);
  const std::string key = "incompressible: ";
  const size_t at = t.find(key);
  const size_t end = t.find('}', at);
  return t.insert(end, ", model: strain");
}

inline std::string cylinder_scene(bool incompressible, double damping_1_s = 20) {
  return "name: bench_cylinder\n"
         "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
         "gravity_m_s2: [0, -9.8, 0]\n" +
         material_yaml(incompressible, damping_1_s, 60, 1070) +
         "components:\n"
         "  - name: cylinder\n"
         "    material: soft\n"
         "    spacing_mm: 6\n"
         "    cylinder: {radius_mm: 19, length_mm: 178}\n"
         "constraints:\n"
         "  - fix: {component: cylinder, region: {box: {min_mm: [-100, -100, -1], max_mm: [100, 100, 0.5]}}}\n";
}

inline std::shared_ptr<const Model> compile_scene(const std::string& yaml) {
  return compile_scenario(parse_scenario_text(yaml, "bench.yaml"));
}

// Scenario text by name, for the command-line modes: cube11, cube11i, cube11s, cube11si, cube22, cube22i, cyl, cyli
// (trailing i = incompressible). Empty for an unknown name.
inline std::string scene_text(const std::string& name, double damping_1_s = 20) {
  if (name == "cube11") return cube_scene(11, false, damping_1_s);
  if (name == "cube11i") return cube_scene(11, true, damping_1_s);
  if (name == "cube11s") return strain_cube_scene(11, false, damping_1_s);
  if (name == "cube11si") return strain_cube_scene(11, true, damping_1_s);
  if (name == "cube22") return cube_scene(22, false, damping_1_s);
  if (name == "cube22i") return cube_scene(22, true, damping_1_s);
  if (name == "cyl") return cylinder_scene(false, damping_1_s);
  if (name == "cyli") return cylinder_scene(true, damping_1_s);
  return {};
}

// The default scene, config/biopsy.yaml, read from this checkout through the normal parse and
// compile path, unchanged (3664 particles: prostate, bladder, rectum, pubic arch, fat). The file's
// own damping is kept; its probe and needle are tools, which the bench does not add.
inline std::shared_ptr<const Model> biopsy_scene() {
  return compile_scenario(parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml"));
}

// Compiled scene by name (the names above, or "biopsy": config/biopsy.yaml); null for an unknown
// name.
inline std::shared_ptr<const Model> scene_by_name(const std::string& name, double damping_1_s = 20) {
  if (name == "biopsy") return biopsy_scene();
  const std::string text = scene_text(name, damping_1_s);
  return text.empty() ? nullptr : compile_scene(text);
}

}  // namespace ps::bench
