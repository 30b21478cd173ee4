// The instrument registry: one ToolKind per kind of instrument (needles, probe, filling), each
// with its scenario section parser, its constructor from the spec, the timeline / live actions it
// takes and how one becomes its command, and what it reports. Its read-out, events and drawing are
// the Tool's own virtuals (engine/step/simulation.h); the window's panels for it are registered on
// the app side (app/gui/tool_panels.h). Modelled on Jolt's one settings class per constraint kind
// and Box2D's joint dispatch in one place: the scene, scripts, recordings, the editor's checks, the
// stress command and the window ask tool_kinds() instead of naming kinds. A new kind is its own
// files plus one line in tool_kinds.cpp (docs/architecture.md, "Adding an instrument kind").
#pragma once
#include <any>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/contract/command.h"
#include "engine/spec/scenario_spec.h"
#include "engine/spec/timeline_entry.h"
#include "engine/step/simulation.h"

namespace YAML {
class Node;
}

namespace ps {

class YamlReader;
struct ToolKind;

// The tools a scene holds, by kind: which kind each index of Simulation::tools() is.
struct ToolSet {
  struct Entry {
    const ToolKind* kind = nullptr;
    int index = -1;                 // in Simulation::tools()
  };
  std::vector<Entry> entries;       // registry order
  const Simulation* sim = nullptr;
  // index in Simulation::tools() of the scene's tool of this kind, -1 when the scene has none
  int index_of(const ToolKind& k) const;
  Tool* get(const ToolKind& k) const;
  // T has `static const ToolKind& kind()`: the typed tool, nullptr when absent
  template <class T>
  T* as() const {
    return static_cast<T*>(get(T::kind()));
  }
  template <class T>
  int index() const {
    return index_of(T::kind());
  }
  template <class T>
  bool has() const {
    return index_of(T::kind()) >= 0;
  }
};

// Per-kind memory while a timeline is turned into commands (the probe's pose commanded so far:
// a probe entry's missing fields keep it). A value: copy it to try a command and keep the copy
// only when the command is taken. Outside the physics thread.
class TimelineMemory {
 public:
  template <class T>
  T& slot(const ToolKind& k) {
    std::any& a = slots_[&k];
    if (!a.has_value()) a = T{};
    return std::any_cast<T&>(a);
  }
  template <class T>
  const T* find(const ToolKind& k) const {
    const auto it = slots_.find(&k);
    return it == slots_.end() ? nullptr : std::any_cast<T>(&it->second);
  }

 private:
  std::map<const ToolKind*, std::any> slots_;
};

// What an action's command is made from, beside the entry itself.
struct CommandContext {
  const ScenarioSpec& spec;
  const Model& model;
  const Tool* tool = nullptr;       // the scene's tool of the kind, nullptr when it has none
  int index = -1;                   // its index in Simulation::tools()
  int64_t tick = 0;                 // the command's stamp
  double dt = 0.0;                  // the tick [s]
  const std::vector<ScriptEntry>* timeline = nullptr;  // the whole script (a script entry), else null
  size_t entry = 0;                 // the entry's index in *timeline
  TimelineMemory& memory;
  const std::string& file;          // for errors
};

// One timeline key (`{t: 1.0, fire: biopsy_1}`): parses the entry's own keys into `e`
// (InputError naming file:line:field).
struct ToolAction {
  const char* key;
  void (*parse)(const YamlReader& r, const YAML::Node& entry, const std::string& where, ScriptEntry& e);
};

struct ToolKind {
  const char* key;                  // its scenario section: "needles", "probe", "filling"
  const char* label;                // one of its instruments, for people and for the Python
                                    // snapshot's `kind`: "needle", "probe", "filling"
  std::vector<ToolAction> actions;  // the timeline / live command keys it takes
  // the scenario section into spec (InputError file:line:field)
  void (*parse_section)(const YamlReader& r, const YAML::Node& node, ScenarioSpec& spec);
  // after every section is parsed (or a spec is built in code): derived spec fields; may be null
  void (*finish_spec)(ScenarioSpec& spec);
  // the scenario's tool of this kind, nullptr when the scenario has none; validates the spec
  // against the model (InputError / CompileError)
  std::unique_ptr<Tool> (*make)(const ScenarioSpec& spec, const std::shared_ptr<const Model>& model);
  // after every kind's tool is built: links to the others (the needle rides on the probe); may be null
  void (*connect)(Tool& self, const ToolSet& tools);
  // an entry of one of `actions` as this kind's command (InputError naming file:line:field, also
  // when the scene has no tool of this kind)
  Command (*command)(const ScriptEntry& e, CommandContext& ctx);
  // the commands it took but adjusted to its limits, as sentences, oldest first; may be null
  std::vector<std::string> (*reports)(const Tool& tool);
};

// Every kind, in the order a scene builds them: that order is part of the state's bits and of the
// command addresses in recordings, so a new kind goes last.
const std::vector<const ToolKind*>& tool_kinds();
const ToolKind* find_tool_kind(const std::string& key);                // by section key, nullptr if none
// Its index in tool_kinds(), as a read-out carries it (ToolReadout::kind); kNoToolKind if unlisted.
uint8_t tool_kind_index(const ToolKind& k);
// The kind that made a read-out, nullptr if none.
const ToolKind* readout_kind(const ToolReadout& r);
const ToolKind* find_tool_kind_for_action(const std::string& action);  // the kind taking a timeline key
// "probe, needle, advance, ..." (for error messages)
std::string tool_action_list();

// Each kind's finish_spec, in registry order.
void finish_tool_specs(ScenarioSpec& spec);
// Builds every kind's tool for `spec` into `sim` (registry order), then connects them.
ToolSet add_scenario_tools(const ScenarioSpec& spec, const std::shared_ptr<const Model>& model, Simulation& sim);

}  // namespace ps
