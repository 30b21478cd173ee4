#include "engine/realtime/script.h"
#include "engine/realtime/script_entry.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/spec/yaml_reader.h"
#include "engine/util/error.h"

namespace ps {

namespace {
constexpr double kMm = 1e-3;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

const char* const kActions[] = {"probe", "needle", "advance", "fire", "deposit_seed", "select", "hole",
                                "rotate", "release", "fill_rate", "fill_to"};

// with_t: a timeline entry (`t` required); without: a live command (no `t` allowed)
ScriptEntry parse_entry(const YamlReader& r, const YAML::Node& n, const std::string& where, bool with_t = true) {
  if (!n.IsMap()) r.fail(n, where, with_t ? "expected a mapping like {t: 1.0, fire: biopsy_1}" : "expected a mapping like {fire: biopsy_1}");
  ScriptEntry e;
  e.line = YamlReader::line_of(n);
  if (with_t) e.t = r.non_negative(r.require(n, where, "t"), where + ".t");
  else if (n["t"]) r.fail(n["t"], where + ".t", "a live command takes no time: it is applied at the next tick");
  // exactly one action key
  for (const char* a : kActions)
    if (n[a].IsDefined()) {
      if (!e.action.empty()) r.fail(n, where, std::string("two actions in one entry: ") + e.action + " and " + a);
      e.action = a;
    }
  if (e.action.empty()) {
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string k = it->first.as<std::string>();
      if (k != "t")
        throw InputError(r.file(), YamlReader::line_of(it->first), where + "." + k,
                         "unknown action (allowed: probe, needle, advance, fire, deposit_seed, select, hole, rotate, release, fill_rate, fill_to)");
    }
    r.fail(n, where, "entry has no action");
  }
  const std::string a = e.action;
  const YAML::Node v = n[a];
  auto name_of = [&](const YAML::Node& x, const std::string& key) {
    if (!x.IsScalar()) r.fail(x, key, "expected an instrument name");
    return x.Scalar();
  };
  if (a == "probe") {
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
  } else if (a == "needle") {
    r.only_keys(n, where, {"t", "needle", "depth_mm"});
    e.target = name_of(v, where + ".needle");
    e.depth = r.number(r.require(n, where, "depth_mm"), where + ".depth_mm") * kMm;
  } else if (a == "advance") {
    r.only_keys(n, where, {"t", "advance", "speed_mm_s"});
    e.target = name_of(v, where + ".advance");
    e.speed = r.number(r.require(n, where, "speed_mm_s"), where + ".speed_mm_s") * kMm;
  } else if (a == "rotate") {
    r.only_keys(n, where, {"t", "rotate", "angle_deg"});
    e.target = name_of(v, where + ".rotate");
    e.angle = r.number(r.require(n, where, "angle_deg"), where + ".angle_deg") * kDeg;
  } else if (a == "hole") {
    r.only_keys(n, where, {"t", "hole", "col", "row"});
    e.target = name_of(v, where + ".hole");
    e.col = r.integer(r.require(n, where, "col"), where + ".col");
    e.row = r.integer(r.require(n, where, "row"), where + ".row");
  } else if (a == "fill_rate") {
    r.only_keys(n, where, {"t", "fill_rate", "ml_s"});
    e.target = name_of(v, where + ".fill_rate");
    e.value = r.number(r.require(n, where, "ml_s"), where + ".ml_s") * 1e-6;
  } else if (a == "fill_to") {
    r.only_keys(n, where, {"t", "fill_to", "ml", "over_s"});
    e.target = name_of(v, where + ".fill_to");
    e.value = r.positive(r.require(n, where, "ml"), where + ".ml") * 1e-6;
    e.over = n["over_s"] ? r.non_negative(n["over_s"], where + ".over_s") : 0.0;
  } else {  // fire, deposit_seed, select, release: the needle's name
    r.only_keys(n, where, {"t", a.c_str()});
    e.target = name_of(v, where + "." + a);
  }
  return e;
}
}  // namespace

Script parse_script_text_unchecked(const std::string& text, const std::string& file);

Script parse_script_text(const std::string& text, const std::string& file) {
  // yaml-cpp's own exceptions (a non-scalar key, a bad conversion) become InputError with the line
  try {
    return parse_script_text_unchecked(text, file);
  } catch (const YAML::Exception& e) {
    throw InputError(file, e.mark.line >= 0 ? static_cast<int>(e.mark.line) + 1 : 0, "", "malformed script: " + e.msg);
  }
}

Script parse_script_text_unchecked(const std::string& text, const std::string& file) {
  YamlReader r(file);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(file, static_cast<int>(e.mark.line) + 1, "", "not valid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw InputError(file, 1, "", "a script is a mapping with a timeline: list");
  r.only_keys(root, "", {"scenario", "duration_s", "timeline"});
  Script s;
  s.file = file;
  if (root["scenario"]) {
    if (!root["scenario"].IsScalar()) r.fail(root["scenario"], "scenario", "expected the scenario's name");
    s.scenario = root["scenario"].Scalar();
  }
  if (root["duration_s"]) s.duration = r.positive(root["duration_s"], "duration_s");
  const YAML::Node tl = r.require(root, "", "timeline");
  if (!tl.IsSequence()) r.fail(tl, "timeline", "expected a list of entries");
  double last = 0.0;
  for (size_t i = 0; i < tl.size(); ++i) {
    const std::string where = "timeline[" + std::to_string(i) + "]";
    ScriptEntry e = parse_entry(r, tl[i], where);
    if (e.t < last)
      throw InputError(file, e.line, where + ".t",
                       "time goes backwards (" + std::to_string(e.t) + " s after " + std::to_string(last) + " s)");
    last = e.t;
    s.entries.push_back(std::move(e));
  }
  if (s.duration > 0.0 && last > s.duration)
    throw InputError(file, s.entries.back().line, "duration_s", "an entry is after the end of the script");
  return s;
}

Script parse_script_file(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path, 0, "", "cannot read script file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_script_text(ss.str(), path);
}

double script_needle_depth(const Script& script, const std::string& needle, double t) {
  const ScriptEntry* prev = nullptr;
  for (const ScriptEntry& e : script.entries) {
    if (e.action != "needle" || e.target != needle) continue;
    if (e.t >= t) {
      if (!prev || e.t == prev->t) return e.depth;
      return prev->depth + (e.depth - prev->depth) * (t - prev->t) / (e.t - prev->t);
    }
    prev = &e;
  }
  return prev ? prev->depth : NAN;
}

ScriptEntry parse_command_text(const std::string& text, const std::string& where) {
  YamlReader r("");
  try {
    const YAML::Node n = YAML::Load(text);
    return parse_entry(r, n, where, false);
  } catch (const YAML::Exception& e) {
    throw InputError("", 0, where, "malformed command: " + e.msg);
  }
}

Command entry_command(const ScriptEntry& e, const Scene& scene, int64_t tick, ProbePose& probe_pose, double needle_speed,
                      const std::string& file) {
  const auto& tools = scene.sim->tools();
  Command c;
  c.tick = tick;
  if (e.action == "probe") {
    if (scene.probe_tool < 0) throw InputError(file, e.line, "probe", "the scene has no probe");
    if (e.has_insertion) probe_pose.insertion = e.insertion;
    if (e.has_offset) probe_pose.offset = e.offset;
    if (e.has_roll) probe_pose.roll = e.roll;
    if (e.has_tilt) probe_pose.tilt = e.tilt;
    if (e.has_yaw) probe_pose.yaw = e.yaw;
    c.kind = CommandKind::ProbeMove;
    c.tool = static_cast<int16_t>(scene.probe_tool);
    c.insertion = probe_pose.insertion;
    for (int i = 0; i < 3; ++i) c.offset[i] = probe_pose.offset[i];
    c.roll = probe_pose.roll;
    c.tilt = probe_pose.tilt;
    c.yaw = probe_pose.yaw;
    c.duration = e.over;
    return c;
  }
  if (e.action == "fill_rate" || e.action == "fill_to") {
    if (scene.filling_tool < 0) throw InputError(file, e.line, e.action, "the scene has no filling");
    c.kind = e.action == "fill_rate" ? CommandKind::FillRate : CommandKind::FillTo;
    c.tool = static_cast<int16_t>(scene.filling_tool);
    c.component = scene.model->find_component(e.target);
    if (c.component < 0) throw InputError(file, e.line, e.action, "the scene has no component '" + e.target + "'");
    c.value = e.value;
    c.duration = e.over;
    return c;
  }
  const int i = scene.needle_tool >= 0 ? tools[scene.needle_tool]->find_item(e.target.c_str()) : -1;
  if (i < 0) throw InputError(file, e.line, e.action, "the scene has no needle named '" + e.target + "'");
  c.tool = static_cast<int16_t>(scene.needle_tool);
  c.item = static_cast<int16_t>(i);
  const NeedleSpec& ns = scene.spec.needles.needles[i];
  if (e.action == "needle" && e.depth > ns.length)
    throw InputError(file, e.line, "depth_mm",
                     "depth " + std::to_string(e.depth * 1e3) + " mm is beyond needle '" + ns.name + "''s length " +
                         std::to_string(ns.length * 1e3) + " mm");
  if (e.action == "needle" && !ns.guide.empty()) {
    // in the probe's guide: the depth along the guide wherever the probe is
    c.kind = CommandKind::NeedleDepth;
    c.insertion = e.depth;
    c.value = needle_speed;
    return c;
  }
  if (e.action == "needle") {
    c.kind = CommandKind::NeedleAim;
    const Vec3 dir = ns.direction.normalized();
    const Vec3 tip = ns.start + e.depth * dir;
    for (int q = 0; q < 3; ++q) {
      c.pos[q] = tip[q];
      c.dir[q] = dir[q];
    }
    c.value = needle_speed;
  } else if (e.action == "advance") {
    c.kind = CommandKind::NeedleAdvance;
    c.value = e.speed;
  } else if (e.action == "rotate") {
    c.kind = CommandKind::NeedleRotate;
    c.value = e.angle;
  } else if (e.action == "hole") {
    c.kind = CommandKind::SelectHole;
    c.col = e.col;
    c.row = e.row;
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

std::vector<Command> script_commands(const Script& script, const Scene& scene) {
  const double dt = scene.model->dt;
  if (!script.scenario.empty() && script.scenario != scene.spec.name)
    throw InputError(script.file, 1, "scenario",
                     "script written for scenario '" + script.scenario + "', not '" + scene.spec.name + "'");
  auto tick_of = [&](double t) { return static_cast<int64_t>(std::llround(t / dt)); };
  std::vector<Command> out;
  // probe pose commanded so far (fields not given keep it)
  ProbePose probe_pose = scene.spec.probe ? scene.spec.probe->pose : ProbePose{};
  for (size_t k = 0; k < script.entries.size(); ++k) {
    const ScriptEntry& e = script.entries[k];
    const int64_t tick = tick_of(e.t);
    // a needle key: moving at the speed that reaches the next key of this needle on time
    double speed = 0.0;
    if (e.action == "needle")
      for (size_t j = k + 1; j < script.entries.size(); ++j) {
        const ScriptEntry& nx = script.entries[j];
        if (nx.action != "needle" || nx.target != e.target) continue;
        const double span = (tick_of(nx.t) - tick) * dt;  // on the tick grid: lands on the key
        if (span > 0) speed = (nx.depth - e.depth) / span;
        break;
      }
    out.push_back(entry_command(e, scene, tick, probe_pose, speed, script.file));
  }
  std::stable_sort(out.begin(), out.end(), [](const Command& a, const Command& b) { return a.tick < b.tick; });
  return out;
}

}  // namespace ps
