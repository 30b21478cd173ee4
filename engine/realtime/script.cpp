#include "engine/realtime/script.h"
#include "engine/realtime/script_entry.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "engine/spec/yaml_reader.h"
#include "engine/tools/tool_kind.h"
#include "engine/util/error.h"

namespace ps {

namespace {

// with_t: a timeline entry (`t` required); without: a live command (no `t` allowed). The action
// key picks the instrument kind that parses the rest (engine/tools/tool_kind.h).
ScriptEntry parse_entry(const YamlReader& r, const YAML::Node& n, const std::string& where, bool with_t = true) {
  if (!n.IsMap()) r.fail(n, where, with_t ? "expected a mapping like {t: 1.0, fire: biopsy_1}" : "expected a mapping like {fire: biopsy_1}");
  ScriptEntry e;
  e.line = YamlReader::line_of(n);
  if (with_t) e.t = r.non_negative(r.require(n, where, "t"), where + ".t");
  else if (n["t"]) r.fail(n["t"], where + ".t", "a live command takes no time: it is applied at the next tick");
  // exactly one action key
  const ToolAction* action = nullptr;
  for (const ToolKind* k : tool_kinds())
    for (const ToolAction& a : k->actions)
      if (n[a.key].IsDefined()) {
        if (action) r.fail(n, where, std::string("two actions in one entry: ") + action->key + " and " + a.key);
        action = &a;
      }
  if (!action) {
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string k = it->first.as<std::string>();
      if (k != "t") throw InputError(r.file(), YamlReader::line_of(it->first), where + "." + k, "unknown action (allowed: " + tool_action_list() + ")");
    }
    r.fail(n, where, "entry has no action");
  }
  e.action = action->key;
  action->parse(r, n, where, e);
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

Command entry_command(const ScriptEntry& e, const Scene& scene, int64_t tick, TimelineMemory& memory, const std::string& file,
                      const std::vector<ScriptEntry>* timeline, size_t index) {
  const ToolKind* kind = find_tool_kind_for_action(e.action);
  if (!kind) throw InputError(file, e.line, e.action, "unknown action (allowed: " + tool_action_list() + ")");
  CommandContext ctx{scene.spec, *scene.model, scene.tools.get(*kind), scene.tools.index_of(*kind), tick, scene.model->dt,
                     timeline, index, memory, file};
  return kind->command(e, ctx);
}

std::vector<Command> script_commands(const Script& script, const Scene& scene) {
  const double dt = scene.model->dt;
  if (!script.scenario.empty() && script.scenario != scene.spec.name)
    throw InputError(script.file, 1, "scenario",
                     "script written for scenario '" + script.scenario + "', not '" + scene.spec.name + "'");
  std::vector<Command> out;
  TimelineMemory memory;
  for (size_t k = 0; k < script.entries.size(); ++k) {
    const ScriptEntry& e = script.entries[k];
    const int64_t tick = static_cast<int64_t>(std::llround(e.t / dt));
    out.push_back(entry_command(e, scene, tick, memory, script.file, &script.entries, k));
  }
  std::stable_sort(out.begin(), out.end(), [](const Command& a, const Command& b) { return a.tick < b.tick; });
  return out;
}

}  // namespace ps
