// Small scenes for the needle tests: a tissue block in a container (bottom held, side faces on
// frictionless walls, top free) and needles given as YAML. Kept small (4 mm lattice, a few
// hundred particles) so each test runs in well under a second or two.
#pragma once
#include <memory>
#include <string>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/simulation.h"
#include "engine/tools/needle/needle.h"

namespace ps::test {

struct BlockOptions {
  double half_width_mm = 12;       // block is [-w, w]^2 x [-depth, 0]
  double depth_mm = 24;
  double spacing_mm = 4;
  double young_kpa = 2.7;
  double k_c = 0.5, k_f = 0.025;
  double damping = 30;
  double puncture = 2.45;          // 0: no membrane
  bool walls = true;               // side faces on frictionless walls
  std::string extra_components;    // appended YAML list items (2-space indent, "  - ...")
  std::string extra_constraints;   // appended YAML list items
  std::string extra_puncture;      // e.g. ", capsule: 3"
};

inline std::string num(double v) {
  std::string s = std::to_string(v);
  return s;
}

inline std::string block_yaml(const BlockOptions& o, const std::string& instruments) {
  const std::string w = num(o.half_width_mm), d = num(o.depth_mm), w1 = num(o.half_width_mm + 1), w_1 = num(o.half_width_mm - 1);
  std::string y = "name: needle_block\n"
                  "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
                  "gravity_m_s2: [0, 0, 0]\n"
                  "materials:\n"
                  "  tissue: {young_kpa: " + num(o.young_kpa) + ", density_kg_m3: 1060, damping_1_s: " + num(o.damping) +
                  ", k_c_n: " + num(o.k_c) + ", k_f_n: " + num(o.k_f) + "}\n"
                  "  bone: {young_kpa: 1000, density_kg_m3: 2000}\n"
                  "components:\n"
                  "  - name: tissue\n"
                  "    material: tissue\n"
                  "    spacing_mm: " + num(o.spacing_mm) + "\n"
                  "    box: {min_mm: [-" + w + ", -" + w + ", -" + d + "], max_mm: [" + w + ", " + w + ", 0]}\n" +
                  o.extra_components +
                  "constraints:\n"
                  "  - fix: {component: tissue, region: {box: {min_mm: [-100, -100, -" + num(o.depth_mm + 1) + "], max_mm: [100, 100, -" +
                  num(o.depth_mm - 1) + "]}}}\n";
  if (o.walls) {
    y += "  - fix: {component: tissue, axes: x, region: {box: {min_mm: [-" + w1 + ", -" + w1 + ", -100], max_mm: [-" + w_1 + ", " + w1 + ", 1]}}}\n";
    y += "  - fix: {component: tissue, axes: x, region: {box: {min_mm: [" + w_1 + ", -" + w1 + ", -100], max_mm: [" + w1 + ", " + w1 + ", 1]}}}\n";
    y += "  - fix: {component: tissue, axes: y, region: {box: {min_mm: [-" + w1 + ", -" + w1 + ", -100], max_mm: [" + w1 + ", -" + w_1 + ", 1]}}}\n";
    y += "  - fix: {component: tissue, axes: y, region: {box: {min_mm: [-" + w1 + ", " + w_1 + ", -100], max_mm: [" + w1 + ", " + w1 + ", 1]}}}\n";
  }
  y += o.extra_constraints;
  y += "needles:\n";
  if (o.puncture > 0) y += "  puncture_n: {tissue: " + num(o.puncture) + o.extra_puncture + "}\n";
  y += "  instruments:\n" + instruments;
  return y;
}

// One vertical 18G needle at (x, y) starting 1 mm above the block, with a script and extra keys.
inline std::string vertical_needle(const std::string& name, double x_mm, double y_mm, const std::string& script,
                                   const std::string& extra = "") {
  return "    - name: " + name + "\n      gauge: 18\n      length_mm: 100\n      start_mm: [" + num(x_mm) + ", " + num(y_mm) +
         ", 1]\n      direction: [0, 0, -1]\n      script: " + script + "\n" + extra;
}

// A 24 x 24 x 16 mm gland block over a tumour block, and an 18G biopsy gun fired 22 mm at 0.5 s
// (biopsy tests, the cores CSV of `prostatesim insert`).
inline std::string biopsy_yaml() {
  return "name: biopsy\n"
         "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
         "gravity_m_s2: [0, 0, 0]\n"
         "materials:\n"
         "  gland: {young_kpa: 15, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.5, k_f_n: 0.025}\n"
         "  lesion: {young_kpa: 30, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.8, k_f_n: 0.04}\n"
         "components:\n"
         "  - {name: prostate, material: gland, spacing_mm: 4, box: {min_mm: [-12, -12, -16], max_mm: [12, 12, 0]}}\n"
         "  - {name: tumour, material: lesion, spacing_mm: 4, box: {min_mm: [-12, -12, -40], max_mm: [12, 12, -20]}}\n"
         "links:\n"
         "  - {a: prostate, b: tumour, distance_mm: 5}\n"
         "constraints:\n"
         "  - fix: {component: tumour, region: {box: {min_mm: [-100, -100, -41], max_mm: [100, 100, -39]}}}\n"
         "needles:\n"
         "  puncture_n: {prostate: 2.5}\n"
         "  instruments:\n"
         "    - name: gun\n"
         "      preset: biopsy_18g\n"
         "      start_mm: [1.3, 0.9, 1]\n"
         "      direction: [0, 0, -1]\n"
         "      script: [[0, 0], [0.4, 8]]\n"
         "      gun: {fire_s: 0.5, stroke_mm: 22, duration_ms: 15}\n";
}

struct NeedleScene {
  ScenarioSpec spec;
  std::shared_ptr<const Model> model;
  std::unique_ptr<Simulation> sim;
  NeedleTool* tool = nullptr;
};

inline NeedleScene make_needle_scene(const std::string& yaml) {
  NeedleScene s;
  s.spec = parse_scenario_text(yaml, "needle_test.yaml");
  s.model = compile_scenario(s.spec);
  s.sim = std::make_unique<Simulation>(s.model);
  auto tool = make_needle_tool(s.model, s.spec.needles);
  s.tool = tool.get();
  s.sim->add_tool(std::move(tool));
  return s;
}

}  // namespace ps::test
