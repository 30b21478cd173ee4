// One way to make a runnable scene from a scenario: the compiled Model, the Simulation and its
// instruments, one per kind the scenario has, in the registry's order (engine/tools/tool_kind.h:
// tool order is part of the state's bits and of the command addresses in recordings). Used by the
// CLI, the app, benchmarks and tests.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/scenario/compile.h"
#include "engine/spec/scenario_spec.h"
#include "engine/step/simulation.h"
#include "engine/tools/tool_kind.h"

namespace ps {

struct Scene {
  ScenarioSpec spec;
  std::shared_ptr<const Model> model;
  std::unique_ptr<Simulation> sim;
  CompileReport report;
  uint64_t content_hash = 0;       // FNV-1a of the scenario file's bytes (0 when built from a spec)
  ToolSet tools;                   // the instruments by kind: tools.as<ProbeTool>(), tools.index_of(kind)
};

// Compiles `spec` and adds its instruments (each only when its section is present). Throws
// InputError / CompileError on bad input.
Scene build_scene(const ScenarioSpec& spec);
// Parses the file, then build_scene; content_hash is set from the file's bytes.
Scene load_scene(const std::string& path);
// The commands the scene's tools took but adjusted to their limits (scripted and live: "probe:
// t=0.15 s: probe command lengthened from ..."), per kind in registry order, oldest first,
// formatted from the tools' report rings (reader side, allocates: between ticks or after the run).
std::vector<std::string> scene_tool_reports(const Scene& scene);
// Hash of a file's bytes (FNV-1a 64); throws InputError when unreadable.
uint64_t file_content_hash(const std::string& path);

}  // namespace ps
