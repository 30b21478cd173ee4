// Needle validation cases (issue 4, item 9). Both are calibration checks, not independent
// predictions: they guard the calibrated shape against changes elsewhere (material mapping,
// integrator, zones), and say which parameter sets which figure.
//
// needle: insertion into a liver-like block at 3 mm/s (config/validation/needle_liver.yaml)
// against the shape Okamura, Simone & O'Leary (2004) measured in bovine liver with an 18G
// needle: a puncture peak of ~2.3-2.6 N near 16-17 mm depth, then a ~1 N plateau (cutting +
// friction) growing with the inserted length. puncture_n sets the peak force, young_kpa (through
// the engine's k_e mapping) the peak depth, k_c_n and k_f_n the plateau.
//
// brachytherapy: the `posterior` needle of config/brachytherapy.yaml (the default anatomy)
// inserted alone through the perineum into the gland, against the prostate brachytherapy
// trainer measurements in ../shared/data/README.md: ~9.0 +- 1.3 N through the perineum, ~5.6 +-
// 0.1 N in the prostate. needles.puncture_n.fat sets the perineal peak, needles.puncture_n.prostate
// (with the fat's k_c_n, k_f_n along the 45 mm of shaft in fat) the prostate peak, and the
// perineal skin layer's young_kpa (scenario overrides) how far the skin tents before it breaks.
#include "app/checks/validate_needle.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "engine/util/error.h"
#include "engine/util/sim_fault.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/needle/needle_output.h"

namespace ps::app {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct NeedleRun {
  std::vector<ForceDepthSample> samples;   // of the needle run, one per tick
  std::vector<NeedleEvent> events;         // chronological
  std::shared_ptr<const Model> model;
};

// Runs the scenario's needle `only` (empty: the scenario's only/first needle; any other needle
// of the plan is left out) for the scenario's duration, or with `insertion_only` until 0.1 s
// after its script first reaches its deepest point (the pull-back is not part of the case).
NeedleRun run_needle_scenario(const std::string& scenario, const std::string& only = "", bool insertion_only = false) {
  ScenarioSpec spec = parse_scenario_file(scenario);
  if (!only.empty()) {
    auto& list = spec.needles.needles;
    std::erase_if(list, [&](const NeedleSpec& n) { return n.name != only; });
    if (list.empty()) throw InputError(scenario, 0, "--needle", "no needle named '" + only + "'");
  }
  NeedleRun out;
  out.model = compile_scenario(spec);
  Simulation sim(out.model);
  auto tool = make_needle_tool(out.model, spec.needles);
  if (!tool) throw InputError(scenario, 0, "needles", "the scenario has no needle");
  NeedleTool& needles = *tool;
  sim.add_tool(std::move(tool));
  ForceDepthRecorder rec(needles.count());
  double duration = spec.duration;
  if (insertion_only && !spec.needles.needles.empty() && !spec.needles.needles[0].script.empty()) {
    const auto& script = spec.needles.needles[0].script;
    const auto deepest = std::max_element(script.begin(), script.end(), [](auto& a, auto& b) { return a.depth < b.depth; });
    duration = std::min(duration, deepest->t + 0.1);
  }
  const int ticks = static_cast<int>(std::lround(duration / out.model->dt));
  for (int i = 0; i < ticks; ++i) {
    if (!sim.tick()) throw SimulationFault(spec.name + ": simulation fault: " + sim.state().fault.describe(*out.model));
    rec.sample(needles, sim.state().time);
  }
  out.samples = rec.samples(0);
  out.events = needles.events().snapshot();
  return out;
}

struct LiverAnswer {
  ForceDepthMetrics fd;
  double force_30mm = kNaN;        // resistance at 30 mm (friction still growing) [N]
  double puncture_depth = kNaN;    // depth of the puncture event [m]
  int punctures = 0;
};

LiverAnswer needle_liver_answer(const std::string& scenario) {
  const NeedleRun run = run_needle_scenario(scenario);
  LiverAnswer a;
  a.fd = force_depth_metrics(run.samples, 20e-3, 25e-3);
  for (const auto& s : run.samples)
    if (s.contacted && std::abs(s.depth - 30e-3) < 0.25e-3) a.force_30mm = s.axial_force;
  for (const auto& e : run.events)
    if (e.kind == NeedleEventKind::Puncture) {
      if (a.punctures == 0) a.puncture_depth = e.depth;
      ++a.punctures;
    }
  return a;
}

struct BrachyAnswer {
  double perineum_peak = kNaN;     // largest tick-averaged force up to the skin's puncture [N]
  double prostate_peak = kNaN;     // largest tick-averaged force after the skin has given way: the capsule peak [N]
  double perineum_event = kNaN, capsule_event = kNaN;   // substep peaks the puncture events carry [N]
  double perineum_depth = kNaN, capsule_depth = kNaN;   // insertion depth at the punctures [m]
  double end_force = kNaN, end_friction = kNaN, end_depth = kNaN;
  int punctures = 0;
};

BrachyAnswer brachytherapy_answer(const std::string& scenario) {
  const NeedleRun run = run_needle_scenario(scenario, "posterior", true);
  const int fat = run.model->find_role(Role::Fat), prostate = run.model->find_role(Role::Prostate);
  BrachyAnswer a;
  double t_skin = kNaN, t_capsule = kNaN;
  for (const auto& e : run.events) {
    if (e.kind != NeedleEventKind::Puncture) continue;
    ++a.punctures;
    if (e.component == fat && std::isnan(t_skin)) { t_skin = e.time; a.perineum_event = e.force; a.perineum_depth = e.depth; }
    if (e.component == prostate && std::isnan(t_capsule)) { t_capsule = e.time; a.capsule_event = e.force; a.capsule_depth = e.depth; }
  }
  if (std::isnan(t_skin) || std::isnan(t_capsule)) return a;
  // the gland phase starts once the force has dropped after the skin's puncture (the first tick
  // whose force is below half the perineal peak) and runs to the end of the insertion
  double f_max = 0.0;
  bool gland = false;
  for (const auto& s : run.samples) {
    if (!s.contacted) continue;
    if (s.time <= t_skin + 1e-3) { f_max = std::max(f_max, s.axial_force); continue; }
    if (!gland && s.axial_force < 0.5 * f_max) gland = true;
    if (gland) a.prostate_peak = std::isnan(a.prostate_peak) ? s.axial_force : std::max(a.prostate_peak, s.axial_force);
  }
  a.perineum_peak = f_max;
  a.end_force = run.samples.back().axial_force;
  a.end_friction = run.samples.back().friction_force;
  a.end_depth = run.samples.back().depth;
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
  cases.push_back(
      {"brachytherapy", "18G brachytherapy needle through the perineum into the gland, default anatomy, vs trainer measurements",
       [](const std::string& src, const std::string&) {
         const BrachyAnswer a = brachytherapy_answer(src + "/config/brachytherapy.yaml");
         return std::vector<ValidationRow>{
             // tolerances: perineum, the measured spread (1.3 N); prostate, 10 % of the value
             // (the issue asks for forces "of the order of" the measurements; docs/validation.md)
             {"brachytherapy", "perineum_peak_N", a.perineum_peak, 9.0, "N", 1.3},
             {"brachytherapy", "prostate_peak_N", a.prostate_peak, 5.6, "N", 0.56},
             {"brachytherapy", "perineum_puncture_event_N", a.perineum_event, kNaN, "N", kNaN},
             {"brachytherapy", "capsule_puncture_event_N", a.capsule_event, kNaN, "N", kNaN},
             {"brachytherapy", "perineum_puncture_depth_mm", 1e3 * a.perineum_depth, kNaN, "mm", kNaN},
             {"brachytherapy", "capsule_puncture_depth_mm", 1e3 * a.capsule_depth, kNaN, "mm", kNaN},
             {"brachytherapy", "force_at_end_N", a.end_force, kNaN, "N", kNaN},
             {"brachytherapy", "friction_at_end_N", a.end_friction, kNaN, "N", kNaN},
             {"brachytherapy", "depth_at_end_mm", 1e3 * a.end_depth, kNaN, "mm", kNaN},
             {"brachytherapy", "punctures", static_cast<double>(a.punctures), 2.0, "", 0.0},
         };
       }});
  return cases;
}

}  // namespace ps::app
