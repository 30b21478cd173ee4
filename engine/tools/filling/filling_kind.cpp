// Organ filling in the instrument registry (engine/tools/tool_kind.h): its `filling:` section,
// its constructor, the `fill_rate` and `fill_to` timeline actions and its reports of commands
// clamped to the physiological rate.
#include "engine/spec/yaml_reader.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/filling/filling_parse.h"
#include "engine/tools/timeline_target.h"
#include "engine/tools/tool_kind.h"

namespace ps {

namespace {

void parse_fill_rate(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  r.only_keys(n, where, {"t", "fill_rate", "ml_s"});
  e.target = timeline_target(r, n["fill_rate"], where + ".fill_rate");
  e.value = r.number(r.require(n, where, "ml_s"), where + ".ml_s") * 1e-6;
}

void parse_fill_to(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  r.only_keys(n, where, {"t", "fill_to", "ml", "over_s"});
  e.target = timeline_target(r, n["fill_to"], where + ".fill_to");
  e.value = r.positive(r.require(n, where, "ml"), where + ".ml") * 1e-6;
  e.over = n["over_s"] ? r.non_negative(n["over_s"], where + ".over_s") : 0.0;
}

Command fill_command(const ScriptEntry& e, CommandContext& ctx) {
  if (!ctx.tool) throw InputError(ctx.file, e.line, e.action, "the scene has no filling");
  Command c;
  c.tick = ctx.tick;
  c.kind = e.action == "fill_rate" ? CommandKind::FillRate : CommandKind::FillTo;
  c.tool = static_cast<int16_t>(ctx.index);
  c.fill.component = ctx.model.find_component(e.target);
  if (c.fill.component < 0) throw InputError(ctx.file, e.line, e.action, "the scene has no component '" + e.target + "'");
  c.fill.value = e.value;
  c.fill.duration = e.over;
  return c;
}

std::unique_ptr<Tool> make_tool(const ScenarioSpec& spec, const std::shared_ptr<const Model>& model) {
  return make_filling_tool(spec, *model);
}

std::vector<std::string> report_lines(const Tool& t) { return static_cast<const FillingTool&>(t).reports(); }

}  // namespace

const ToolKind& FillingTool::kind() {
  static const ToolKind k{
      "filling",     "filling", {{"fill_rate", parse_fill_rate}, {"fill_to", parse_fill_to}}, parse_filling_section, nullptr, make_tool,
      nullptr,       fill_command,    report_lines,
  };
  return k;
}

}  // namespace ps
