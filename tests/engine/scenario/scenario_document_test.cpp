// The scenario editor's core (engine/scenario/scenario_document.h): edits by key path keep the
// comments and key order, saved files reopen to the same compiled model, invalid edits are
// refused naming the field, a failed save leaves the file intact, a hand-broken file opens with
// its error, and an edit changes the simulation as expected.
#include "engine/scenario/scenario_document.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/step/simulation.h"
#include "engine/tools/needle/needle.h"
#include "engine/util/error.h"

namespace ps {
namespace {

namespace fs = std::filesystem;

const char* kScene =
    "# Instructor exercise: one needle into a block (comments must survive editing)\n"
    "name: doc_block\n"
    "time: {dt_ms: 1, substeps: 1, duration_s: 1}\n"
    "gravity_m_s2: [0, 0, 0]\n"
    "materials:\n"
    "  # soft tissue, stiffness in kPa\n"
    "  tissue: {young_kpa: 2.7, density_kg_m3: 1060, damping_1_s: 30, k_c_n: 0.5, k_f_n: 0.025}\n"
    "  bone: {young_kpa: 1000, density_kg_m3: 2000}\n"
    "components:\n"
    "  - name: tissue\n"
    "    material: tissue\n"
    "    spacing_mm: 4\n"
    "    box: {min_mm: [-12, -12, -24], max_mm: [12, 12, 0]}\n"
    "  - name: bone\n"
    "    type: rigid\n"
    "    kinematic: true\n"
    "    material: bone\n"
    "    spacing_mm: 4\n"
    "    fill: surface\n"
    "    box: {min_mm: [-12, -12, -44], max_mm: [12, 12, -32]}\n"
    "constraints:\n"
    "  - fix: {component: tissue, region: {box: {min_mm: [-100, -100, -25], max_mm: [100, 100, -23]}}}\n"
    "  # side faces on frictionless walls\n"
    "  - fix: {component: tissue, axes: x, region: {box: {min_mm: [-13, -13, -100], max_mm: [-11, 13, 1]}}}\n"
    "  - fix: {component: tissue, axes: x, region: {box: {min_mm: [11, -13, -100], max_mm: [13, 13, 1]}}}\n"
    "  - fix: {component: tissue, axes: y, region: {box: {min_mm: [-13, -13, -100], max_mm: [13, -11, 1]}}}\n"
    "  - fix: {component: tissue, axes: y, region: {box: {min_mm: [-13, 11, -100], max_mm: [13, 13, 1]}}}\n"
    "tags:\n"
    "  - name: lesion_a\n"
    "    component: tissue\n"
    "    region: {sphere: {center_mm: [-6, 0, -12], radius_mm: 3}}   # left of the needle\n"
    "  - name: lesion_b\n"
    "    component: tissue\n"
    "    region: {sphere: {center_mm: [6, 0, -12], radius_mm: 3}}\n"
    "needles:\n"
    "  puncture_n: {tissue: 2.45}   # membrane of the block's top face\n"
    "  instruments:\n"
    "    - name: n\n"
    "      gauge: 18\n"
    "      length_mm: 100\n"
    "      start_mm: [0, 0, 1]\n"
    "      direction: [0, 0, -1]\n"
    "      script: [[0, 0], [0.5, 13]]\n"
    "      target_mm: [0, 0, -12]\n";

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("ps_doc_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(ScenarioDocument, OpensValidAndLocatesValues) {
  ScenarioDocument d(kScene, "doc.yaml");
  ASSERT_TRUE(d.valid()) << d.error()->message;
  EXPECT_EQ(d.value_text("materials.tissue.young_kpa"), "2.7");
  EXPECT_EQ(d.value_text("tags[lesion_b].region.sphere.center_mm"), "[6, 0, -12]");
  EXPECT_EQ(d.value_text("tags[1].region.sphere.radius_mm"), "3");
  EXPECT_EQ(d.value_text("needles.instruments[n].script"), "[[0, 0], [0.5, 13]]");
  EXPECT_EQ(d.value_text("needles.puncture_n.tissue"), "2.45");
  EXPECT_EQ(d.value_text("name"), "doc_block");
  EXPECT_NE(d.model_hash(), 0u);
}

TEST(ScenarioDocument, SaveThenOpenGivesTheSameTextAndModelKeepingComments) {
  const fs::path dir = temp_dir("roundtrip");
  ScenarioDocument d(kScene, (dir / "ex.yaml").string());
  const uint64_t before = d.model_hash();
  ASSERT_TRUE(d.set_number("materials.tissue.young_kpa", 5.5).ok);
  ASSERT_TRUE(d.set_vec3("tags[lesion_a].region.sphere.center_mm", Vec3(-7, 1, -14)).ok);
  ASSERT_TRUE(d.set("needles.instruments[n].planned_site", "right mid lateral").ok);   // new key, block mapping
  ASSERT_TRUE(d.set_number("materials.bone.damping_1_s", 20).ok);                     // new key, flow mapping
  EXPECT_NE(d.model_hash(), before) << "stiffness and lesion changed the model";
  d.save();
  EXPECT_FALSE(d.modified());
  const std::string saved = read(dir / "ex.yaml");
  EXPECT_EQ(saved, d.text());
  for (const char* c : {"# Instructor exercise", "# soft tissue, stiffness in kPa", "# left of the needle", "# membrane of the block"})
    EXPECT_NE(saved.find(c), std::string::npos) << c;
  EXPECT_NE(saved.find("tissue: {young_kpa: 5.5, density_kg_m3: 1060"), std::string::npos) << saved;
  EXPECT_NE(saved.find("bone: {young_kpa: 1000, density_kg_m3: 2000, damping_1_s: 20}"), std::string::npos) << saved;
  EXPECT_NE(saved.find("      target_mm: [0, 0, -12]\n      planned_site: right mid lateral\n"), std::string::npos) << saved;
  // key order: everything else where it was
  EXPECT_LT(saved.find("materials:"), saved.find("components:"));
  EXPECT_LT(saved.find("tags:"), saved.find("needles:"));
  const ScenarioDocument again = ScenarioDocument::open((dir / "ex.yaml").string());
  ASSERT_TRUE(again.valid());
  EXPECT_EQ(again.model_hash(), d.model_hash());
  EXPECT_EQ(again.spec()->needles.needles[0].planned_site, "right mid lateral");
  EXPECT_NEAR(again.spec()->tags[0].region.center.z(), -14e-3, 1e-12);
  // an unedited open -> save is byte-identical
  ScenarioDocument plain(kScene, (dir / "plain.yaml").string());
  plain.save();
  EXPECT_EQ(read(dir / "plain.yaml"), kScene);
  fs::remove_all(dir);
}

TEST(ScenarioDocument, InvalidEditsAreRefusedNamingTheFieldAndChangeNothing) {
  ScenarioDocument d(kScene, "doc.yaml");
  struct Case {
    std::string path, value, field, words;
  };
  const std::vector<Case> cases = {
      {"materials.tissue.young_kpa", "-5", "materials.tissue.young_kpa", "-5"},
      {"materials.tissue.damping_1_s", "-1", "materials.tissue.damping_1_s", ""},
      {"needles.instruments[n].target_mm", "[0, 0, 30]", "needles.instruments[0].target_mm", "outside every organ"},
      {"tags[lesion_b].region.sphere.center_mm", "[-4, 0, -12]", "tags[1].region", "overlaps lesion 'lesion_a'"},
      {"needles.instruments[n].script", "[[0, 0], [0.5, 40]]", "needles.instruments[0].script", "through bone 'bone'"},
      {"needles.puncture_n.tissue", "-2", "needles.puncture_n.tissue", ""},
      {"materials.nothing.young_kpa", "3", "materials.nothing", "no such key"},
  };
  for (const Case& c : cases) {
    const EditResult r = d.set(c.path, c.value);
    EXPECT_FALSE(r.ok) << c.path << " = " << c.value;
    ASSERT_TRUE(r.issue.has_value()) << c.path;
    EXPECT_EQ(r.issue->field, c.field) << r.issue->message;
    EXPECT_NE(r.issue->message.find(c.words), std::string::npos) << r.issue->message;
    // the message is the reason only: file, line and field travel beside it (the editor prints
    // them in front, once)
    EXPECT_EQ(r.issue->message.find("doc.yaml"), std::string::npos) << r.issue->message;
    EXPECT_EQ(r.issue->message.find("'" + r.issue->field + "'"), std::string::npos) << r.issue->message;
    EXPECT_EQ(d.text(), kScene) << "a refused edit leaves the document unchanged";
    EXPECT_TRUE(d.valid());
  }
  EXPECT_FALSE(d.can_undo());
}

TEST(ScenarioDocument, UndoAndRedoWalkTheAcceptedEdits) {
  ScenarioDocument d(kScene, "doc.yaml");
  const uint64_t h0 = d.model_hash();
  ASSERT_TRUE(d.set_number("materials.tissue.young_kpa", 4).ok);
  const uint64_t h1 = d.model_hash();
  ASSERT_TRUE(d.set_number("materials.tissue.young_kpa", 8).ok);
  EXPECT_EQ(d.value_text("materials.tissue.young_kpa"), "8");
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.value_text("materials.tissue.young_kpa"), "4");
  EXPECT_EQ(d.model_hash(), h1);
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.text(), kScene);
  EXPECT_EQ(d.model_hash(), h0);
  EXPECT_FALSE(d.undo());
  ASSERT_TRUE(d.redo());
  EXPECT_EQ(d.model_hash(), h1);
  // a new edit after an undo drops the redo branch
  ASSERT_TRUE(d.set_number("materials.tissue.young_kpa", 6).ok);
  EXPECT_FALSE(d.can_redo());
}

TEST(ScenarioDocument, FailedSaveLeavesTheOriginalIntact) {
  const fs::path dir = temp_dir("failsave");
  const fs::path file = dir / "ex.yaml";
  std::ofstream(file) << kScene;
  ScenarioDocument d = ScenarioDocument::open(file.string());
  ASSERT_TRUE(d.set_number("materials.tissue.young_kpa", 9).ok);
  // the temporary file cannot be created: a folder stands where it would go
  fs::create_directories(file.string() + ".tmp." + std::to_string(::getpid()));
  EXPECT_THROW(d.save(), std::runtime_error);
  EXPECT_EQ(read(file), kScene);
  EXPECT_TRUE(d.modified());
  fs::remove_all(dir);
}

TEST(ScenarioDocument, HandEditedInvalidFileOpensWithItsError) {
  std::string bad = kScene;
  bad.replace(bad.find("young_kpa: 2.7"), 14, "young_kpa: -3");
  ScenarioDocument d(bad, "hand.yaml");
  ASSERT_FALSE(d.valid());
  EXPECT_EQ(d.error()->field, "materials.tissue.young_kpa");
  EXPECT_EQ(d.error()->line, 7);
  EXPECT_EQ(d.spec(), nullptr);
  EXPECT_THROW(d.save("never.yaml"), InputError);
  EXPECT_FALSE(fs::exists("never.yaml"));
  // fixing the field makes it valid
  ASSERT_TRUE(d.set_number("materials.tissue.young_kpa", 2.7).ok);
  EXPECT_TRUE(d.valid());
  EXPECT_EQ(d.text(), kScene);
  // broken YAML syntax too
  ScenarioDocument y("name: [unclosed\n", "y.yaml");
  ASSERT_FALSE(y.valid());
  EXPECT_GT(y.error()->line, 0);
}

// Puncture force of the needle in the document's scene [N].
double puncture_force(const ScenarioDocument& d) {
  Simulation sim(d.model());
  auto tool = make_needle_tool(d.model(), d.spec()->needles);
  NeedleTool* t = tool.get();
  sim.add_tool(std::move(tool));
  for (int i = 0; i < 700; ++i) {
    if (!sim.tick()) {
      ADD_FAILURE() << sim.state().fault.describe(*d.model());
      return NAN;
    }
    for (const NeedleEvent& e : t->events().snapshot())
      if (e.kind == NeedleEventKind::Puncture) return e.force;
  }
  return NAN;
}

TEST(ScenarioDocument, AnEditThroughTheCommandPathChangesTheSimulation) {
  ScenarioDocument d(kScene, "doc.yaml");
  // a longer stroke, so that the stiffer membrane is reached before the script ends
  ASSERT_TRUE(d.set("needles.instruments[n].script", "[[0, 0], [0.5, 18]]").ok);
  const double f1 = puncture_force(d);
  ASSERT_TRUE(d.set_number("needles.puncture_n.tissue", 3.675).ok);
  const double f2 = puncture_force(d);
  std::printf("puncture force: %.3f N at puncture_n 2.45 N, %.3f N at 3.675 N (ratio %.3f)\n", f1, f2, f2 / f1);
  EXPECT_NEAR(f1, 2.45, 0.25);
  EXPECT_NEAR(f2 / f1, 1.5, 0.15) << "the membrane breaks at the edited weight";
}

}  // namespace
}  // namespace ps

namespace ps {
namespace {

// The shipped scenes, with their comments, block and flow mappings and a YAML anchor shared by the
// lesion tag and its stiffness override: probe pose, lesion place, material, bladder fill edits.
TEST(ScenarioDocument, ShippedScenesEditInPlace) {
  const std::string dir = std::string(PROSTATESIM_SOURCE_DIR) + "/config/";
  ScenarioDocument b = ScenarioDocument::open(dir + "biopsy.yaml");
  ASSERT_TRUE(b.valid()) << b.error()->message;
  const std::string before = b.text();
  const uint64_t h0 = b.model_hash();
  ASSERT_TRUE(b.set_number("probe.pose.insertion_mm", 35).ok);
  ASSERT_TRUE(b.set_number("probe.pose.tilt_deg", 5).ok);           // added to the flow mapping
  EXPECT_NEAR(b.spec()->probe->pose.tilt, 5.0 * 3.14159265358979 / 180.0, 1e-9);
  EXPECT_EQ(b.model_hash(), h0) << "the probe is not part of the tissue model";
  // the lesion's region is an anchor (&lesion) that the stiffness override reuses (*lesion)
  ASSERT_TRUE(b.set_vec3("tags[lesion].region.ellipsoid.center_mm", Vec3(-9, -7, 2)).ok);
  EXPECT_NEAR(b.spec()->tags[0].region.center.x(), -9e-3, 1e-12);
  EXPECT_NEAR(b.spec()->overrides[0].region.center.x(), -9e-3, 1e-12) << "the override follows the anchor";
  EXPECT_NE(b.model_hash(), h0);
  const EditResult alias = b.set_vec3("overrides[0].region.ellipsoid.center_mm", Vec3(0, 0, 0));
  EXPECT_FALSE(alias.ok) << "an edit through the alias *lesion would move the tag too";
  EXPECT_EQ(alias.issue->field, "overrides[0].region");
  EXPECT_NE(alias.issue->message.find("alias (*lesion)"), std::string::npos) << alias.issue->message;
  // everything else as written: same lines apart from the three edited ones
  auto lines = [](const std::string& s) {
    std::vector<std::string> v;
    std::istringstream in(s);
    for (std::string l; std::getline(in, l);) v.push_back(l);
    return v;
  };
  const auto a = lines(before), c = lines(b.text());
  ASSERT_EQ(a.size(), c.size());
  int changed = 0;
  for (size_t i = 0; i < a.size(); ++i) changed += a[i] != c[i];
  EXPECT_EQ(changed, 2) << b.text();  // the probe pose line and the lesion line

  ScenarioDocument f = ScenarioDocument::open(dir + "bladder_filling.yaml");
  ASSERT_TRUE(f.valid()) << f.error()->message;
  ASSERT_TRUE(f.spec()->filling.has_value());
  ASSERT_TRUE(f.set_number("filling.max_rate_ml_s", 50).ok);
  EXPECT_NEAR(f.spec()->filling->max_rate, 50e-6, 1e-12);
  const EditResult neg = f.set_number("filling.max_rate_ml_s", -5);
  EXPECT_FALSE(neg.ok);
  EXPECT_EQ(neg.issue->field, "filling.max_rate_ml_s") << neg.issue->message;
}

}  // namespace
}  // namespace ps

namespace ps {
namespace {

// Lists: a lesion, a needle, a seed added and removed, in block and flow lists, with undo and redo
// giving back the exact texts, refusals leaving the text as it was, and a save -> open round trip.
TEST(ScenarioDocument, AddsAndRemovesListItemsWithUndo) {
  ScenarioDocument d(kScene, "doc.yaml");
  ASSERT_TRUE(d.valid()) << d.error()->message;
  const std::string t0 = d.text();
  EXPECT_EQ(d.item_count("tags"), 2);
  // a lesion (block list of block mappings): a new "- {...}" line after the last item
  const EditResult add = d.add_item("tags", "{name: lesion_c, component: tissue, region: {sphere: {center_mm: [0, 8, -16], radius_mm: 3}}}");
  ASSERT_TRUE(add.ok) << add.issue->message;
  ASSERT_EQ(d.spec()->tags.size(), 3u);
  EXPECT_EQ(d.spec()->tags[2].name, "lesion_c");
  EXPECT_NEAR(d.spec()->tags[2].region.center.y(), 8e-3, 1e-12);
  EXPECT_NE(d.text().find("    region: {sphere: {center_mm: [6, 0, -12], radius_mm: 3}}\n  - {name: lesion_c"), std::string::npos) << d.text();
  EXPECT_NE(d.text().find("# left of the needle"), std::string::npos);
  const std::string t1 = d.text();
  // one overlapping lesion_a is refused, naming the new item's region; the text stays
  const EditResult overlap = d.add_item("tags", "{name: lesion_d, component: tissue, region: {sphere: {center_mm: [-5, 0, -12], radius_mm: 3}}}");
  EXPECT_FALSE(overlap.ok);
  ASSERT_TRUE(overlap.issue.has_value());
  EXPECT_EQ(overlap.issue->field, "tags[3].region") << overlap.issue->message;
  EXPECT_NE(overlap.issue->message.find("overlaps lesion 'lesion_a'"), std::string::npos) << overlap.issue->message;
  EXPECT_EQ(d.text(), t1);
  // a second needle (block list), then seeds (a missing key, then a flow list)
  ASSERT_TRUE(d.add_item("needles.instruments", "{name: n2, gauge: 18, length_mm: 100, start_mm: [4, 4, 1], direction: [0, 0, -1], script: [[0, 0], [0.5, 12]]}").ok);
  ASSERT_EQ(d.spec()->needles.needles.size(), 2u);
  EXPECT_EQ(d.spec()->needles.needles[1].name, "n2");
  const std::string t2 = d.text();
  EditResult seed = d.add_item("needles.instruments[n2].seeds_mm", "10");
  ASSERT_TRUE(seed.ok) << seed.issue->message;
  ASSERT_TRUE(d.add_item("needles.instruments[n2].seeds_mm", "6").ok);
  ASSERT_EQ(d.spec()->needles.needles[1].seed_depths.size(), 2u);
  EXPECT_NE(d.text().find("seeds_mm: [10, 6]}"), std::string::npos) << d.text();
  // a seed beyond the scripted depth is refused by the parser, naming the seed
  const EditResult deep = d.add_item("needles.instruments[n2].seeds_mm", "40");
  EXPECT_FALSE(deep.ok);
  EXPECT_NE(deep.issue->field.find("seeds_mm"), std::string::npos) << deep.issue->field << ": " << deep.issue->message;
  ASSERT_TRUE(d.remove_item("needles.instruments[n2].seeds_mm[0]").ok);
  EXPECT_NE(d.text().find("seeds_mm: [6]}"), std::string::npos) << d.text();
  ASSERT_TRUE(d.remove_item("needles.instruments[n2].seeds_mm[0]").ok);
  EXPECT_NE(d.text().find("seeds_mm: []}"), std::string::npos) << d.text();
  EXPECT_TRUE(d.spec()->needles.needles[1].seed_depths.empty());
  // removing the needle gives back the text before it, byte for byte
  ASSERT_TRUE(d.remove_item("needles.instruments[n2]").ok);
  EXPECT_EQ(d.text(), t1);
  ASSERT_TRUE(d.remove_item("tags[lesion_c]").ok);
  EXPECT_EQ(d.text(), t0);
  // undo walks back through every accepted edit; redo forward again
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.text(), t1);
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.text(), t2);
  ASSERT_TRUE(d.redo());
  EXPECT_EQ(d.spec()->needles.needles[1].seed_depths.size(), 1u);
  // bad paths are refused naming the path
  EXPECT_FALSE(d.remove_item("tags[nope]").ok);
  EXPECT_FALSE(d.remove_item("tags").ok);
  EXPECT_FALSE(d.add_item("tags[0]", "1").ok);
  // save -> open: the same text and the same compiled model
  const fs::path dir = temp_dir("items");
  const std::string file = (dir / "edited.yaml").string();
  d.save(file);
  const ScenarioDocument again = ScenarioDocument::open(file);
  ASSERT_TRUE(again.valid());
  EXPECT_EQ(again.text(), d.text());
  EXPECT_EQ(again.model_hash(), d.model_hash());
  fs::remove_all(dir);
}

// The only item of a block list: the key keeps "[]" (and its comment); a flow list's middle item.
TEST(ScenarioDocument, RemovingTheLastItemOfABlockListLeavesAnEmptyList) {
  const std::string text = "a:\n  b: 1\nitems:   # the list\n  # first\n  - {x: 1}\nafter: 2\nflow: [1, 2, 3]\n";
  const std::string t = text_with_item_removed(text, "items[0]");
  EXPECT_EQ(t, "a:\n  b: 1\nitems: [] # the list\nafter: 2\nflow: [1, 2, 3]\n");
  EXPECT_EQ(text_with_item_removed(text, "flow[1]"), "a:\n  b: 1\nitems:   # the list\n  # first\n  - {x: 1}\nafter: 2\nflow: [1, 3]\n");
  EXPECT_EQ(text_with_item_removed(text, "flow[2]"), "a:\n  b: 1\nitems:   # the list\n  # first\n  - {x: 1}\nafter: 2\nflow: [1, 2]\n");
  EXPECT_EQ(text_with_item_removed(text, "flow[0]"), "a:\n  b: 1\nitems:   # the list\n  # first\n  - {x: 1}\nafter: 2\nflow: [2, 3]\n");
  EXPECT_EQ(text_with_item_added(text, "items", "{x: 2}"), "a:\n  b: 1\nitems:   # the list\n  # first\n  - {x: 1}\n  - {x: 2}\nafter: 2\nflow: [1, 2, 3]\n");
  EXPECT_EQ(text_with_item_added("l: []\n", "l", "7"), "l: [7]\n");
}

}  // namespace
}  // namespace ps
