// The instrument registry (engine/tools/tool_kind.h): every kind named once with its own actions,
// scenes holding their tools by kind in the registry's order, timeline entries parsed and turned
// into commands by the kind that owns their action.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "engine/realtime/script.h"
#include "engine/realtime/script_entry.h"
#include "engine/sim/scene.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/tool_kind.h"
#include "engine/util/error.h"

namespace ps {
namespace {

std::string config(const std::string& name) { return std::string(PROSTATESIM_SOURCE_DIR) + "/config/" + name; }

TEST(ToolKinds, EachKindAndEachActionIsNamedOnce) {
  std::set<std::string> keys, actions;
  for (const ToolKind* k : tool_kinds()) {
    ASSERT_NE(k, nullptr);
    EXPECT_TRUE(keys.insert(k->key).second) << "two kinds with the key " << k->key;
    ASSERT_NE(k->parse_section, nullptr) << k->key;
    ASSERT_NE(k->make, nullptr) << k->key;
    ASSERT_NE(k->command, nullptr) << k->key;
    EXPECT_FALSE(k->actions.empty()) << k->key;
    for (const ToolAction& a : k->actions) {
      EXPECT_TRUE(actions.insert(a.key).second) << "two kinds take the action " << a.key;
      EXPECT_EQ(find_tool_kind_for_action(a.key), k) << a.key;
    }
    EXPECT_EQ(find_tool_kind(k->key), k);
  }
  EXPECT_EQ(find_tool_kind("scalpel"), nullptr);
  EXPECT_EQ(find_tool_kind_for_action("teleport"), nullptr);
  // the build order is part of the state's bits: needles, probe, filling
  ASSERT_EQ(tool_kinds().size(), 3u);
  EXPECT_EQ(tool_kinds()[0], &NeedleTool::kind());
  EXPECT_EQ(tool_kinds()[1], &ProbeTool::kind());
  EXPECT_EQ(tool_kinds()[2], &FillingTool::kind());
}

TEST(ToolKinds, SceneHoldsItsToolsByKindInRegistryOrder) {
  const Scene sc = load_scene(config("biopsy.yaml"));
  ASSERT_GE(sc.tools.entries.size(), 2u);
  int last = -1;
  for (const ToolSet::Entry& e : sc.tools.entries) {
    EXPECT_GT(e.index, last) << e.kind->key << ": tools are added in registry order";
    last = e.index;
  }
  const NeedleTool* needles = sc.tools.as<NeedleTool>();
  const ProbeTool* probe = sc.tools.as<ProbeTool>();
  ASSERT_NE(needles, nullptr);
  ASSERT_NE(probe, nullptr);
  EXPECT_EQ(static_cast<const Tool*>(needles), sc.sim->tools()[static_cast<size_t>(sc.tools.index<NeedleTool>())].get());
  EXPECT_EQ(static_cast<const Tool*>(probe), sc.sim->tools()[static_cast<size_t>(sc.tools.index<ProbeTool>())].get());
  EXPECT_FALSE(sc.tools.has<FillingTool>()) << "config/biopsy.yaml fills no organ";
  EXPECT_EQ(sc.tools.as<FillingTool>(), nullptr);
  EXPECT_EQ(sc.tools.index<FillingTool>(), -1);
  // the needle kind's connect hook put the guide needle on the probe
  for (int i = 0; i < needles->count(); ++i)
    if (!needles->spec(i).guide.empty()) EXPECT_TRUE(needles->guided(i)) << needles->spec(i).name;
}

TEST(ToolKinds, AnEntryBecomesTheCommandOfTheKindThatOwnsItsAction) {
  const Scene sc = load_scene(config("biopsy.yaml"));
  TimelineMemory memory;
  const Command probe = entry_command(parse_command_text("{probe: {roll_deg: 30}, over_s: 0.5}"), sc, 7, memory, "");
  EXPECT_EQ(probe.kind, CommandKind::ProbeMove);
  EXPECT_EQ(probe.tick, 7);
  EXPECT_EQ(probe.tool, sc.tools.index<ProbeTool>());
  EXPECT_NEAR(probe.probe.roll, 30.0 * 3.14159265358979323846 / 180.0, 1e-15);
  EXPECT_EQ(probe.probe.duration, 0.5);
  // fields the entry does not give keep the pose commanded so far (the scenario's before any)
  EXPECT_EQ(probe.probe.insertion, sc.spec.probe->pose.insertion);
  const Command tilt = entry_command(parse_command_text("{probe: {tilt_deg: 5}}"), sc, 8, memory, "");
  EXPECT_EQ(tilt.probe.roll, probe.probe.roll) << "the roll commanded before is kept";
  EXPECT_EQ(commanded_probe_pose(memory, sc.spec).roll, probe.probe.roll);

  const std::string needle = sc.spec.needles.needles.at(0).name;
  const Command fire = entry_command(parse_command_text("{fire: " + needle + "}"), sc, 9, memory, "");
  EXPECT_EQ(fire.kind, CommandKind::FireGun);
  EXPECT_EQ(fire.tool, sc.tools.index<NeedleTool>());
  EXPECT_EQ(fire.item, 0);
}

TEST(ToolKinds, TimelineMemoryIsAValue) {
  const Scene sc = load_scene(config("biopsy.yaml"));
  TimelineMemory kept;
  entry_command(parse_command_text("{probe: {roll_deg: 10}}"), sc, 0, kept, "");
  TimelineMemory tried = kept;  // a command tried on a copy, then refused: the copy is dropped
  entry_command(parse_command_text("{probe: {roll_deg: 40}}"), sc, 1, tried, "");
  EXPECT_NEAR(commanded_probe_pose(kept, sc.spec).roll, 10.0 * 3.14159265358979323846 / 180.0, 1e-15);
  EXPECT_NEAR(commanded_probe_pose(tried, sc.spec).roll, 40.0 * 3.14159265358979323846 / 180.0, 1e-15);
}

TEST(ToolKinds, AnActionOfAKindTheSceneLacksIsRefusedNamingTheLine) {
  const Scene sc = load_scene(config("biopsy.yaml"));
  const Script s = parse_script_text("timeline:\n  - {t: 0.1, fill_to: bladder, ml: 200}\n", "fill.yaml");
  try {
    script_commands(s, sc);
    FAIL() << "a filling command in a scene without filling was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("the scene has no filling"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ps
