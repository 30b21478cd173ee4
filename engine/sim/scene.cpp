#include "engine/sim/scene.h"

#include <fstream>
#include <sstream>

#include "engine/scenario/parse_yaml.h"
#include "engine/util/error.h"
#include "engine/util/state_io.h"

namespace ps {

Scene build_scene(const ScenarioSpec& spec) {
  Scene sc;
  sc.spec = spec;
  finish_tool_specs(sc.spec);  // e.g. a needle in the probe's guide starts on it (a spec built in code)
  sc.model = compile_scenario(sc.spec, &sc.report);
  sc.sim = std::make_unique<Simulation>(sc.model);
  sc.tools = add_scenario_tools(sc.spec, sc.model, *sc.sim);
  return sc;
}

uint64_t file_content_hash(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "", "cannot read file");
  std::ostringstream ss;
  ss << f.rdbuf();
  const std::string s = ss.str();
  return fnv1a(s.data(), s.size());
}

Scene load_scene(const std::string& path) {
  const uint64_t h = file_content_hash(path);
  Scene sc = build_scene(parse_scenario_file(path));
  sc.content_hash = h;
  return sc;
}

std::vector<std::string> scene_tool_reports(const Scene& scene) {
  std::vector<std::string> out;
  if (!scene.sim) return out;
  for (const ToolSet::Entry& e : scene.tools.entries)
    if (e.kind->reports)
      for (const std::string& l : e.kind->reports(*scene.sim->tools()[static_cast<size_t>(e.index)]))
        out.push_back(std::string(e.kind->key) + ": " + l);
  return out;
}

}  // namespace ps
