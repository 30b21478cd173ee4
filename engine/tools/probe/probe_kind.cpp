// The endorectal probe in the instrument registry (engine/tools/tool_kind.h): its `probe:`
// section, its constructor, the `probe` timeline action (a pose reached over `over_s`) and its
// reports of moves lengthened to its speed limits.
#include <cmath>

#include "engine/spec/yaml_reader.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/probe/probe_parse.h"
#include "engine/tools/tool_kind.h"

namespace ps {

namespace {

constexpr double kMm = 1e-3;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

void parse_probe_entry(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  const YAML::Node v = n["probe"];
  r.only_keys(n, where, {"t", "probe", "over_s"});
  r.only_keys(v, where + ".probe", {"insertion_mm", "offset_mm", "roll_deg", "tilt_deg", "yaw_deg"});
  const std::string w = where + ".probe";
  if (v["insertion_mm"]) { e.has_insertion = true; e.insertion = r.number(v["insertion_mm"], w + ".insertion_mm") * kMm; }
  if (v["offset_mm"]) {
    const YAML::Node o = v["offset_mm"];
    if (!o.IsSequence() || o.size() != 3) r.fail(o, w + ".offset_mm", "expected [x, y, z]");
    e.has_offset = true;
    for (int i = 0; i < 3; ++i) e.offset[i] = r.number(o[i], w + ".offset_mm") * kMm;
  }
  if (v["roll_deg"]) { e.has_roll = true; e.roll = r.number(v["roll_deg"], w + ".roll_deg") * kDeg; }
  if (v["tilt_deg"]) { e.has_tilt = true; e.tilt = r.number(v["tilt_deg"], w + ".tilt_deg") * kDeg; }
  if (v["yaw_deg"]) { e.has_yaw = true; e.yaw = r.number(v["yaw_deg"], w + ".yaw_deg") * kDeg; }
  e.over = n["over_s"] ? r.non_negative(n["over_s"], where + ".over_s") : 0.0;
}


Command probe_command(const ScriptEntry& e, CommandContext& ctx) {
  if (!ctx.tool) throw InputError(ctx.file, e.line, "probe", "the scene has no probe");
  CommandedPose& mem = ctx.memory.slot<CommandedPose>(ProbeTool::kind());
  if (!mem.set) {
    mem.pose = ctx.spec.probe ? ctx.spec.probe->pose : ProbePose{};
    mem.set = true;
  }
  ProbePose& p = mem.pose;
  if (e.has_insertion) p.insertion = e.insertion;
  if (e.has_offset) p.offset = e.offset;
  if (e.has_roll) p.roll = e.roll;
  if (e.has_tilt) p.tilt = e.tilt;
  if (e.has_yaw) p.yaw = e.yaw;
  Command c;
  c.kind = CommandKind::ProbeMove;
  c.tick = ctx.tick;
  c.tool = static_cast<int16_t>(ctx.index);
  c.probe.insertion = p.insertion;
  for (int i = 0; i < 3; ++i) c.probe.offset[i] = p.offset[i];
  c.probe.roll = p.roll;
  c.probe.tilt = p.tilt;
  c.probe.yaw = p.yaw;
  c.probe.duration = e.over;
  return c;
}

std::unique_ptr<Tool> make_tool(const ScenarioSpec& spec, const std::shared_ptr<const Model>& model) {
  return make_probe_tool(spec, *model);
}

std::vector<std::string> report_lines(const Tool& t) { return static_cast<const ProbeTool&>(t).reports(); }

}  // namespace

ProbePose commanded_probe_pose(const TimelineMemory& memory, const ScenarioSpec& spec) {
  const CommandedPose* mem = memory.find<CommandedPose>(ProbeTool::kind());
  if (mem && mem->set) return mem->pose;
  return spec.probe ? spec.probe->pose : ProbePose{};
}

const ToolKind& ProbeTool::kind() {
  static const ToolKind k{
      "probe", "probe", {{"probe", parse_probe_entry}}, parse_probe_section, nullptr, make_tool, nullptr, probe_command, report_lines,
  };
  return k;
}

}  // namespace ps
