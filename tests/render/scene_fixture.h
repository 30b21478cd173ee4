// Test scenes for the renderer: a default scenario compiled and stepped in lock-step on the
// test's thread, and a Snapshot filled the way the physics thread publishes one (positions,
// the tools' DrawList, the needle read-out).
#pragma once
#include <memory>
#include <string>

#include "engine/realtime/snapshot.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/simulation.h"
#include "engine/tools/filling.h"
#include "engine/tools/needle.h"
#include "engine/tools/probe.h"
#include "engine/tools/probe_guide.h"
#include "render/render_scene.h"

namespace ps::test {

struct SceneFixture {
  ScenarioSpec spec;
  std::shared_ptr<const Model> model;
  std::unique_ptr<Simulation> sim;
  NeedleTool* needles = nullptr;
  ProbeTool* probe = nullptr;

  explicit SceneFixture(const std::string& file) {
    spec = parse_scenario_file(file);
    model = compile_scenario(spec, nullptr);
    sim = std::make_unique<Simulation>(model);
    if (auto t = make_needle_tool(model, spec.needles)) { needles = t.get(); sim->add_tool(std::move(t)); }
    if (auto t = make_probe_tool(spec, *model)) { probe = t.get(); sim->add_tool(std::move(t)); }
    if (auto t = make_filling_tool(spec, *model)) sim->add_tool(std::move(t));
  }
  std::string urethra() const {
    for (const auto& c : spec.components)
      if (c.name == "prostate") return render::urethra_file_beside(c.shape.mesh.file);
    return {};
  }
  void fill(Snapshot& s) const {
    const State& st = sim->state();
    s.tick = 0;
    s.time = st.time;
    s.x.resize(3 * st.x.size());
    for (size_t p = 0; p < st.x.size(); ++p)
      for (int k = 0; k < 3; ++k) s.x[3 * p + k] = static_cast<float>(st.x[p][k]);
    s.draw.clear();
    for (const auto& t : sim->tools()) t->draw(s.draw, *model, st);
    s.tools.clear();
    if (probe) {
      ToolReadout r;
      r.kind = ToolReadout::Probe;
      std::snprintf(r.name.data(), r.name.size(), "probe");
      r.tip = probe->frame().capsule.tip;
      r.axis = probe->frame().axis();
      s.tools.push_back(r);
    }
    if (needles && needles->count() > 0) {
      const NeedleReadout& n = needles->readout(0);
      ToolReadout r;
      r.kind = ToolReadout::Needle;
      std::snprintf(r.name.data(), r.name.size(), "%s", needles->spec(0).name.c_str());
      r.tip = n.tip;
      r.axis = n.direction;
      r.depth = n.depth;
      r.force = n.axial_force_tick;
      r.active = true;
      s.tools.push_back(r);
    }
  }
};

}  // namespace ps::test
