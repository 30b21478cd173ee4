// The needles in the instrument registry (engine/tools/tool_kind.h): the `needles:` section, the
// tool built from it, the needle timeline actions (depth keys, advance, fire, deposit_seed,
// select, hole, rotate, release) and the link to the probe whose guide and template they ride in.
#include <cmath>

#include "engine/model/role.h"
#include "engine/spec/yaml_reader.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/needle/needle_spec_yaml.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/probe/probe_guide.h"
#include "engine/tools/timeline_target.h"
#include "engine/tools/tool_kind.h"

namespace ps {

namespace {

constexpr double kMm = 1e-3;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

void parse_depth(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  r.only_keys(n, where, {"t", "needle", "depth_mm"});
  e.target = timeline_target(r, n["needle"], where + ".needle");
  e.depth = r.number(r.require(n, where, "depth_mm"), where + ".depth_mm") * kMm;
}

void parse_advance(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  r.only_keys(n, where, {"t", "advance", "speed_mm_s"});
  e.target = timeline_target(r, n["advance"], where + ".advance");
  e.speed = r.number(r.require(n, where, "speed_mm_s"), where + ".speed_mm_s") * kMm;
}

void parse_rotate(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  r.only_keys(n, where, {"t", "rotate", "angle_deg"});
  e.target = timeline_target(r, n["rotate"], where + ".rotate");
  e.angle = r.number(r.require(n, where, "angle_deg"), where + ".angle_deg") * kDeg;
}

void parse_hole(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  r.only_keys(n, where, {"t", "hole", "col", "row"});
  e.target = timeline_target(r, n["hole"], where + ".hole");
  e.col = r.integer(r.require(n, where, "col"), where + ".col");
  e.row = r.integer(r.require(n, where, "row"), where + ".row");
}

// fire, deposit_seed, select, release: the needle's name only
void parse_name_only(const YamlReader& r, const YAML::Node& n, const std::string& where, ScriptEntry& e) {
  r.only_keys(n, where, {"t", e.action.c_str()});
  e.target = timeline_target(r, n[e.action], where + "." + e.action);
}

// A depth key of a script moves on at the speed that reaches the same needle's next key on time
// (on the tick grid, so it lands on the key); held at the last key and for a live command.
double speed_to_next_key(const ScriptEntry& e, const CommandContext& ctx) {
  if (!ctx.timeline) return 0.0;
  const auto& tl = *ctx.timeline;
  for (size_t j = ctx.entry + 1; j < tl.size(); ++j) {
    const ScriptEntry& nx = tl[j];
    if (nx.action != "needle" || nx.target != e.target) continue;
    const double span = (static_cast<int64_t>(std::llround(nx.t / ctx.dt)) - ctx.tick) * ctx.dt;
    return span > 0 ? (nx.depth - e.depth) / span : 0.0;
  }
  return 0.0;
}

Command needle_command(const ScriptEntry& e, CommandContext& ctx) {
  const int i = ctx.tool ? ctx.tool->find_item(e.target.c_str()) : -1;
  if (i < 0) throw InputError(ctx.file, e.line, e.action, "the scene has no needle named '" + e.target + "'");
  Command c;
  c.tick = ctx.tick;
  c.tool = static_cast<int16_t>(ctx.index);
  c.item = static_cast<int16_t>(i);
  const NeedleSpec& ns = ctx.spec.needles.needles[static_cast<size_t>(i)];
  if (e.action == "needle" && e.depth > ns.length)
    throw InputError(ctx.file, e.line, "depth_mm",
                     "depth " + std::to_string(e.depth * 1e3) + " mm is beyond needle '" + ns.name + "''s length " +
                         std::to_string(ns.length * 1e3) + " mm");
  if (e.action == "needle" && !ns.guide.empty()) {
    // in the probe's guide: the depth along the guide wherever the probe is
    c.kind = CommandKind::NeedleDepth;
    c.needle.depth = e.depth;
    c.needle.speed = speed_to_next_key(e, ctx);
    return c;
  }
  if (e.action == "needle") {
    c.kind = CommandKind::NeedleAim;
    const Vec3 dir = ns.direction.normalized();
    const Vec3 tip = ns.start + e.depth * dir;
    for (int q = 0; q < 3; ++q) {
      c.needle.pos[q] = tip[q];
      c.needle.dir[q] = dir[q];
    }
    c.needle.speed = speed_to_next_key(e, ctx);
  } else if (e.action == "advance") {
    c.kind = CommandKind::NeedleAdvance;
    c.needle.speed = e.speed;
  } else if (e.action == "rotate") {
    c.kind = CommandKind::NeedleRotate;
    c.needle.angle = e.angle;
  } else if (e.action == "hole") {
    c.kind = CommandKind::SelectHole;
    c.needle.col = e.col;
    c.needle.row = e.row;
  } else if (e.action == "fire") {
    c.kind = CommandKind::FireGun;
  } else if (e.action == "deposit_seed") {
    c.kind = CommandKind::DepositSeed;
  } else if (e.action == "select") {
    c.kind = CommandKind::SelectNeedle;
  } else if (e.action == "release") {
    c.kind = CommandKind::NeedleRelease;
  }
  return c;
}

void parse_section(const YamlReader& r, const YAML::Node& node, ScenarioSpec& spec) { spec.needles = parse_needles_yaml(r, node); }

std::unique_ptr<Tool> make_tool(const ScenarioSpec& spec, const std::shared_ptr<const Model>& model) {
  std::unique_ptr<NeedleTool> t = make_needle_tool(model, spec.needles);
  if (!t) return t;
  t->set_urethra(model->urethra, kUrethraRadius);  // watched when the anatomy has its line
  // the gland whose capsule a core or a seed needle may overshoot: the zoned one, else by role
  t->set_gland(spec.prostate_zones ? model->find_component(spec.prostate_zones->component) : model->find_role(Role::Prostate));
  return t;
}

// SelectHole aims along the probe's template; a needle in the guide follows the probe's pose
void connect_tool(Tool& self, const ToolSet& tools) {
  if (const ProbeTool* probe = tools.as<ProbeTool>()) static_cast<NeedleTool&>(self).attach_probe(probe);
}

}  // namespace

const ToolKind& NeedleTool::kind() {
  static const ToolKind k{
      "needles",
      "needle",
      {{"needle", parse_depth},
       {"advance", parse_advance},
       {"fire", parse_name_only},
       {"deposit_seed", parse_name_only},
       {"select", parse_name_only},
       {"hole", parse_hole},
       {"rotate", parse_rotate},
       {"release", parse_name_only}},
      parse_section,
      place_guided_needles,  // a needle in the probe's guide starts on it
      make_tool,
      connect_tool,
      needle_command,
      nullptr,
  };
  return k;
}

}  // namespace ps
