// Needle insertion into a liver-like block at 3 mm/s (config/validation/needle_liver.yaml)
// against the shape Okamura, Simone & O'Leary (2004) measured in bovine liver with an 18G
// needle: a puncture peak of ~2.3-2.6 N near 16-17 mm depth, then a ~1 N plateau (cutting +
// friction) growing with the inserted length.
// This is a calibration check, not an independent prediction: puncture_n sets the peak force,
// young_kpa (through the engine's k_e mapping) the peak depth, k_c_n and k_f_n the plateau. It
// guards the calibrated shape against changes elsewhere (material mapping, integrator, zones).
#include "app/validate_needle.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/needle_output.h"

namespace ps::app {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct LiverAnswer {
  ForceDepthMetrics fd;
  double force_30mm = kNaN;        // resistance at 30 mm (friction still growing) [N]
  double puncture_depth = kNaN;    // depth of the puncture event [m]
  int punctures = 0;
};

LiverAnswer needle_liver_answer(const std::string& scenario) {
  const ScenarioSpec spec = parse_scenario_file(scenario);
  auto model = compile_scenario(spec);
  Simulation sim(model);
  auto tool = make_needle_tool(model, spec.needles);
  if (!tool) throw std::runtime_error(scenario + ": no needle");
  NeedleTool& needles = *tool;
  sim.add_tool(std::move(tool));
  ForceDepthRecorder rec(needles.count());
  const int ticks = static_cast<int>(std::lround(spec.duration / model->dt));
  for (int i = 0; i < ticks; ++i) {
    if (!sim.tick()) throw std::runtime_error(spec.name + ": simulation fault: " + sim.state().fault.describe(*model));
    rec.sample(needles, sim.state().time);
  }
  LiverAnswer a;
  a.fd = force_depth_metrics(rec.samples(0), 20e-3, 25e-3);
  for (const auto& s : rec.samples(0))
    if (s.contacted && std::abs(s.depth - 30e-3) < 0.25e-3) a.force_30mm = s.axial_force;
  for (const auto& e : needles.events().snapshot())
    if (e.kind == NeedleEventKind::Puncture) {
      if (a.punctures == 0) a.puncture_depth = e.depth;
      ++a.punctures;
    }
  return a;
}

}  // namespace

std::vector<ValidationCase> needle_validation_cases() {
  std::vector<ValidationCase> cases;
  cases.push_back(
      {"needle", "18G needle at 3 mm/s into a liver-like block vs Okamura 2004 (puncture peak, plateau)",
       [](const std::string& src, const std::string&) {
         const LiverAnswer a = needle_liver_answer(src + "/config/validation/needle_liver.yaml");
         return std::vector<ValidationRow>{
             // tolerances: the published ranges (2.3-2.6 N, 16-17 mm) widened by half a lattice
             // spacing in depth; plateau "~1 N" read as 0.7-1.3 N
             {"needle", "peak_force_N", a.fd.peak_force, 2.45, "N", 0.15},
             {"needle", "peak_depth_mm", 1e3 * a.fd.peak_depth, 16.5, "mm", 2.0},
             {"needle", "plateau_force_N", a.fd.plateau_force, 1.0, "N", 0.3},
             {"needle", "force_at_30mm_N", a.force_30mm, kNaN, "N", kNaN},
             {"needle", "puncture_depth_mm", 1e3 * a.puncture_depth, kNaN, "mm", kNaN},
             {"needle", "punctures", static_cast<double>(a.punctures), 1.0, "", 0.0},
         };
       }});
  return cases;
}

}  // namespace ps::app
