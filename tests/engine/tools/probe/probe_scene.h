// The probe and filling test scene (config/validation/probe_pelvis_box.yaml) with its instruments,
// shared by the probe, filling, guide and command-queue tests and bench/probe_bench.cpp.
#pragma once
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"

namespace ps::test {

inline std::string probe_scene_path() { return std::string(PROSTATESIM_SOURCE_DIR) + "/config/validation/probe_pelvis_box.yaml"; }

inline std::string probe_scene_yaml() {
  std::ifstream in(probe_scene_path());
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct ProbeScene {
  ScenarioSpec spec;
  std::shared_ptr<const Model> m;
  std::unique_ptr<Simulation> sim;
  ProbeTool* probe = nullptr;
  FillingTool* filling = nullptr;  // only when asked for
  NeedleTool* needles = nullptr;   // when the spec has needles
  double worst_penetration = 0.0;  // tests' scratch: deepest particle inside the probe after any tick [m]
};

// Compiles `spec` and adds its needles (if any), its probe and, when `with_filling`, its filling.
inline ProbeScene build_probe_scene(const ScenarioSpec& spec, bool with_filling) {
  ProbeScene s;
  s.spec = spec;
  s.m = compile_scenario(s.spec);
  s.sim = std::make_unique<Simulation>(s.m);
  if (auto n = make_needle_tool(s.m, s.spec.needles)) {
    s.needles = n.get();
    s.sim->add_tool(std::move(n));
  }
  auto p = make_probe_tool(s.spec, *s.m);
  s.probe = p.get();
  s.sim->add_tool(std::move(p));
  if (with_filling) {
    auto f = make_filling_tool(s.spec, *s.m);
    s.filling = f.get();
    s.sim->add_tool(std::move(f));
  }
  return s;
}

inline ProbeScene build_probe_scene(bool with_filling) {
  return build_probe_scene(parse_scenario_file(probe_scene_path()), with_filling);
}

}  // namespace ps::test
