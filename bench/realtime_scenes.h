// The default scenes with a needle inserting, as the realtime benchmark and the error study run
// them (bench/realtime_bench.cpp, bench/fast_error.cpp):
//   biopsy         config/biopsy.yaml; its needle (held in the file, moved by the trainee) gets
//                  the script 0 -> 40 mm in 1 s along the guide: through the rectal wall at
//                  ~8 mm, into the gland
//   brachytherapy  config/brachytherapy.yaml as written (its needles advance at 20 mm/s from 0.3 s)
//   bladder_filling config/bladder_filling.yaml as written (no needle; the bladder fills)
// `triplets`, `substeps`, `mass_scaling` override solver.triplets (0: all), time.substeps and
// solver.mass_scaling (0 off, 1 on) and solver.multirate (0 off, 1 on) when >= 0.
#pragma once
#include <string>

#include "engine/scenario/parse_yaml.h"

namespace ps::bench {

// `file`: a scenario file to read instead of config/<name>.yaml (the same scene otherwise
// discretised: bench --fast-error's REF_FILE), with the same needle script added.
inline ScenarioSpec realtime_scene(const std::string& name, int triplets = -1, int substeps = -1,
                                   int mass_scaling = -1, int multirate = -1, const std::string& file = "") {
  ScenarioSpec spec = parse_scenario_file(file.empty() ? std::string(PROSTATESIM_SOURCE_DIR) + "/config/" + name + ".yaml" : file);
  if (name == "biopsy" && !spec.needles.needles.empty() && spec.needles.needles[0].script.empty())
    spec.needles.needles[0].script = {{0.0, 0.0}, {1.0, 40e-3}};
  if (triplets >= 0) spec.max_triplets = triplets;
  if (substeps > 0) spec.substeps = substeps;
  if (mass_scaling >= 0) spec.mass_scaling = mass_scaling != 0;
  if (multirate >= 0) spec.multirate = multirate != 0;
  return spec;
}

// where the error study's target particle is: the lesion centre (biopsy), the first needle's
// deepest planned point (brachytherapy), the prostate's centre, the frame's origin, in a scene
// without a needle (bladder_filling: the gland pushed by the filling bladder) [m]
inline Vec3 realtime_target(const std::string& name, const ScenarioSpec& spec) {
  if (name == "biopsy") return Vec3(9e-3, -7e-3, 2e-3);
  if (spec.needles.needles.empty()) return Vec3::Zero();
  const NeedleSpec& n = spec.needles.needles.at(0);
  double depth = 0.0;
  for (const auto& pt : n.script) depth = std::max(depth, pt.depth);
  return n.start + depth * n.direction.normalized();
}

}  // namespace ps::bench
