// The registry's lookups and the scene-building loop over every kind (engine/tools/tool_kind.h).
#include "engine/tools/tool_kind.h"

namespace ps {

int ToolSet::index_of(const ToolKind& k) const {
  for (const Entry& e : entries)
    if (e.kind == &k) return e.index;
  return -1;
}

Tool* ToolSet::get(const ToolKind& k) const {
  const int i = index_of(k);
  return i < 0 || !sim ? nullptr : sim->tools()[static_cast<size_t>(i)].get();
}

const ToolKind* find_tool_kind(const std::string& key) {
  for (const ToolKind* k : tool_kinds())
    if (key == k->key) return k;
  return nullptr;
}

uint8_t tool_kind_index(const ToolKind& k) {
  const auto& kinds = tool_kinds();
  for (size_t i = 0; i < kinds.size(); ++i)
    if (kinds[i] == &k) return static_cast<uint8_t>(i);
  return kNoToolKind;
}

const ToolKind* readout_kind(const ToolReadout& r) {
  const auto& kinds = tool_kinds();
  return r.kind < kinds.size() ? kinds[r.kind] : nullptr;
}

const ToolKind* find_tool_kind_for_action(const std::string& action) {
  for (const ToolKind* k : tool_kinds())
    for (const ToolAction& a : k->actions)
      if (action == a.key) return k;
  return nullptr;
}

std::string tool_action_list() {
  std::string out;
  for (const ToolKind* k : tool_kinds())
    for (const ToolAction& a : k->actions) out += (out.empty() ? "" : ", ") + std::string(a.key);
  return out;
}

void finish_tool_specs(ScenarioSpec& spec) {
  for (const ToolKind* k : tool_kinds())
    if (k->finish_spec) k->finish_spec(spec);
}

ToolSet add_scenario_tools(const ScenarioSpec& spec, const std::shared_ptr<const Model>& model, Simulation& sim) {
  ToolSet set;
  set.sim = &sim;
  for (const ToolKind* k : tool_kinds())
    if (std::unique_ptr<Tool> t = k->make(spec, model)) {
      set.entries.push_back({k, static_cast<int>(sim.tools().size())});
      sim.add_tool(std::move(t));
    }
  for (const ToolSet::Entry& e : set.entries)
    if (e.kind->connect) e.kind->connect(*sim.tools()[static_cast<size_t>(e.index)], set);
  return set;
}

}  // namespace ps
