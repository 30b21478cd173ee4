#include "engine/sim/scene.h"

#include <fstream>
#include <sstream>

#include "engine/metrics/metrics_options.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/filling.h"
#include "engine/tools/needle.h"
#include "engine/tools/probe.h"
#include "engine/tools/probe_guide.h"
#include "engine/util/error.h"
#include "engine/util/state_io.h"

namespace ps {

Scene build_scene(const ScenarioSpec& spec) {
  Scene sc;
  sc.spec = spec;
  place_guided_needles(sc.spec);  // a needle in the probe's guide starts on it (a spec built in code)
  sc.model = compile_scenario(sc.spec, &sc.report);
  sc.sim = std::make_unique<Simulation>(sc.model);
  NeedleTool* needles = nullptr;
  ProbeTool* probe = nullptr;
  // order: needles, probe, filling (as the CLI has always added them: same bits as before)
  if (auto t = make_needle_tool(sc.model, sc.spec.needles)) {
    needles = t.get();
    sc.needle_tool = static_cast<int>(sc.sim->tools().size());
    sc.sim->add_tool(std::move(t));
  }
  if (auto t = make_probe_tool(sc.spec, *sc.model)) {
    probe = t.get();
    sc.probe_tool = static_cast<int>(sc.sim->tools().size());
    sc.sim->add_tool(std::move(t));
  }
  if (auto t = make_filling_tool(sc.spec, *sc.model)) {
    sc.filling_tool = static_cast<int>(sc.sim->tools().size());
    sc.sim->add_tool(std::move(t));
  }
  if (needles && probe) needles->attach_probe(probe);
  if (needles && sc.spec.prostate_zones) {  // the anatomy's urethra line, when it has one
    const MetricsOptions opt = metrics_options_for(sc.spec, *sc.model);
    needles->set_urethra(opt.urethra, opt.urethra_radius);
  }
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
  const auto& tools = scene.sim->tools();
  if (scene.probe_tool >= 0)
    for (const std::string& l : static_cast<const ProbeTool&>(*tools.at(static_cast<size_t>(scene.probe_tool))).reports())
      out.push_back("probe: " + l);
  if (scene.filling_tool >= 0)
    for (const std::string& l : static_cast<const FillingTool&>(*tools.at(static_cast<size_t>(scene.filling_tool))).reports())
      out.push_back("filling: " + l);
  return out;
}

}  // namespace ps
