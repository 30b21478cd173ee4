// The editor's commands (app/editor/editor_commands.h), without a window: each widget's edit in
// file units, refusals naming the field (negative stiffness, a target outside every organ,
// overlapping lesions, a needle path through bone), the needle plan (template hole, planned core,
// seeds), and edits through this command path changing the simulation as expected: a needle
// target moved 5 mm scores about 5 mm more error after the run.
#include "app/editor/editor_commands.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/metrics/session_metrics.h"
#include "engine/tools/needle/needle.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps::editor {
namespace {

namespace fs = std::filesystem;

std::string block_scene(const std::string& target = "[0, 0, -12]") {
  std::string y = test::block_yaml(test::BlockOptions{}, test::vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]", "      target_mm: " + target + "\n"));
  y += "tags:\n  - name: lesion_a\n    component: tissue\n    region: {sphere: {center_mm: [-6, 0, -12], radius_mm: 3}}\n";
  return y;
}

// Runs the document's scene for `seconds` with the session metrics; mean targeting error [mm].
double run_error_mm(const EditorCommands& c, double seconds) {
  Scene s = c.preview_scene();
  const auto& tool = *s.tools.as<NeedleTool>();
  SessionMetrics m(*s.model, tool);
  const long ticks = std::lround(seconds / s.model->dt);
  for (long i = 0; i < ticks; ++i) {
    EXPECT_TRUE(s.sim->tick());
    m.observe(tool, s.sim->state());
  }
  return 1e3 * m.finish(tool, s.sim->state()).mean_error;
}

TEST(EditorCommands, MovingTheTargetFiveMillimetresAddsFiveMillimetresOfError) {
  EditorCommands c(ScenarioDocument(block_scene(), "block.yaml"));
  ASSERT_TRUE(c.doc().valid()) << c.doc().error()->message;
  const double on = run_error_mm(c, 0.8);
  const EditResult r = c.set_needle_target("n", Vec3(5, 0, -12));
  ASSERT_TRUE(r.ok) << r.issue->message;
  const double off = run_error_mm(c, 0.8);
  std::printf("targeting error: %.3f mm on target, %.3f mm after the editor moved the target 5 mm\n", on, off);
  EXPECT_LT(on, 1.0);
  EXPECT_NEAR(off, 5.0, 1.0);
  ASSERT_TRUE(c.undo());
  EXPECT_NEAR(run_error_mm(c, 0.8), on, 1e-12) << "undo gives back the same simulation";
}

TEST(EditorCommands, MaterialsLesionsAndRefusalsNameTheField) {
  EditorCommands c(ScenarioDocument(block_scene(), "block.yaml"));
  ASSERT_TRUE(c.doc().valid());
  EXPECT_EQ(c.organs(), (std::vector<std::string>{"tissue"}));
  EXPECT_EQ(c.material_of("tissue"), "tissue");
  const uint64_t h0 = c.doc().model_hash();
  ASSERT_TRUE(c.set_material("tissue", "young_kpa", 5.4).ok);
  EXPECT_NEAR(*c.material_value("tissue", "young_kpa"), 5.4, 1e-12);
  EXPECT_NE(c.doc().model_hash(), h0) << "stiffer tissue is another model";
  // negative stiffness
  const EditResult neg = c.set_material("tissue", "young_kpa", -1);
  ASSERT_FALSE(neg.ok);
  EXPECT_EQ(neg.issue->field.rfind("materials.tissue", 0), 0u) << neg.issue->field;
  // a target outside every organ
  const EditResult out = c.set_needle_target("n", Vec3(0, 0, 40));
  ASSERT_FALSE(out.ok);
  EXPECT_NE(out.issue->message.find("outside every organ"), std::string::npos) << out.issue->message;
  EXPECT_NE(out.issue->field.find("target_mm"), std::string::npos) << out.issue->field;
  // lesions: move, resize, add, overlap refused, remove
  ASSERT_EQ(c.regions().size(), 1u);
  EXPECT_EQ(c.regions()[0].center_mm, Vec3(-6, 0, -12));
  ASSERT_TRUE(c.move_region("lesion_a", Vec3(-7, 1, -12)).ok);
  ASSERT_TRUE(c.resize_region("lesion_a", Vec3::Constant(2.5)).ok);
  EXPECT_NEAR(c.spec()->tags[0].region.radius, 2.5e-3, 1e-12);
  ASSERT_TRUE(c.add_lesion("lesion_b", "tissue", Vec3(6, 0, -12), 3).ok);
  const EditResult overlap = c.move_region("lesion_b", Vec3(-6, 0, -12));
  ASSERT_FALSE(overlap.ok);
  EXPECT_NE(overlap.issue->message.find("overlaps"), std::string::npos) << overlap.issue->message;
  EXPECT_EQ(c.regions()[1].center_mm, Vec3(6, 0, -12)) << "refused: unchanged";
  ASSERT_TRUE(c.remove_tag("lesion_b").ok);
  EXPECT_EQ(c.regions().size(), 1u);
  // the message of a refused edit is found by the widget bound to the key, and cleared by an accepted edit
  FieldErrors errs;
  errs.note("needles.instruments[n].target_mm", out);
  EXPECT_FALSE(errs.for_key("needles.instruments[n].target_mm").empty());
  errs.note("needles.instruments[n].target_mm", c.set_needle_target("n", Vec3(0, 0, -10)));
  EXPECT_TRUE(errs.for_key("needles.instruments[n].target_mm").empty());
  // a puncture weight
  ASSERT_TRUE(c.set_puncture_weight("tissue", 3.0).ok);
  EXPECT_NEAR(c.spec()->needles.puncture[0].second, 3.0, 1e-12);
}

TEST(EditorCommands, NeedlePlanOnTheShippedScenes) {
  const std::string dir = std::string(PROSTATESIM_SOURCE_DIR) + "/config/";
  // brachytherapy: a needle through template hole (6, 2) to 60 mm, two seeds on it
  // the shipped scene's `anterior_edge` needle is aimed at the pubic arch on purpose: the editor
  // opens it with that error shown, and removing the needle makes it valid
  EditorCommands b = EditorCommands::open(dir + "brachytherapy_template.yaml");
  ASSERT_FALSE(b.doc().valid());
  EXPECT_NE(b.doc().error()->message.find("goes through bone 'pubic_arch'"), std::string::npos) << b.doc().error()->message;
  EXPECT_NE(b.doc().error()->field.find("needles.instruments[1]"), std::string::npos) << b.doc().error()->field;
  ASSERT_TRUE(b.remove_needle("anterior_edge").ok);
  ASSERT_TRUE(b.doc().valid()) << b.doc().error()->message;
  const std::string base = b.doc().text();
  const size_t n0 = b.spec()->needles.needles.size();
  EditResult r = b.add_template_needle("t_new", 6, 2, 60.0);
  ASSERT_TRUE(r.ok) << r.issue->field << ": " << r.issue->message;
  ASSERT_EQ(b.spec()->needles.needles.size(), n0 + 1);
  const NeedleSpec& t = b.spec()->needles.needles.back();
  EXPECT_NEAR(t.direction.z(), 1.0, 1e-3) << "template holes run along the probe axis";
  EXPECT_NEAR(t.script.back().depth, 60e-3, 1e-12);
  ASSERT_TRUE(b.add_seed("t_new", 55).ok);
  ASSERT_TRUE(b.add_seed("t_new", 50).ok);
  EXPECT_EQ(b.spec()->needles.needles.back().seed_depths.size(), 2u);
  EXPECT_FALSE(b.add_seed("t_new", 80).ok) << "a seed beyond the scripted depth";
  EXPECT_FALSE(b.add_template_needle("t_off", 40, 2, 60.0).ok) << "a hole off the grid";
  // the needle planned again at the anterior edge: refused, through bone
  const EditResult bone = b.doc().add_item("needles.instruments",
                                           "{name: anterior_edge, preset: brachy_18g, start_mm: [15, 10, -66], direction: [0, 0, 1], script: [[0, 0], [0.3, 0], [3.3, 60]]}");
  ASSERT_FALSE(bone.ok);
  EXPECT_NE(bone.issue->message.find("through bone"), std::string::npos) << bone.issue->message;
  ASSERT_TRUE(b.remove_seed("t_new", 0).ok);
  ASSERT_TRUE(b.remove_needle("t_new").ok);
  EXPECT_EQ(b.doc().text(), base);
  // biopsy: a planned core in the right mid lateral zone aimed at the lesion; probe and filling
  EditorCommands p = EditorCommands::open(dir + "biopsy.yaml");
  ASSERT_TRUE(p.doc().valid());
  r = p.add_biopsy_core("core_rml", "right mid lateral", Vec3(9, -7, 2));
  ASSERT_TRUE(r.ok) << r.issue->field << ": " << r.issue->message;
  EXPECT_EQ(p.spec()->needles.needles.back().planned_site, "right mid lateral");
  ASSERT_TRUE(p.set_probe_pose("insertion_mm", 38).ok);
  EXPECT_NEAR(p.spec()->probe->pose.insertion, 38e-3, 1e-12);
  EXPECT_FALSE(p.set_probe_pose("nonsense", 1).ok);
  EditorCommands f = EditorCommands::open(dir + "bladder_filling.yaml");
  ASSERT_TRUE(f.doc().valid());
  ASSERT_TRUE(f.set_max_fill_rate_ml_s(20).ok);
  EXPECT_FALSE(f.set_fill_target_ml(0, -10).ok);
}

// The filling panel's segments (issue 13: a segment given as target_factor showed "nan", the
// panel read only target_ml and rate_ml_s): config/bladder_filling.yaml's only segment is
// `target_factor: 2.0`; it shows its factor and the volume it means in ml, editing the volume in ml
// keeps the file's form (the factor), and the compiled filling reaches that volume.
TEST(EditorCommands, AFillSegmentGivenAsAFactorShowsAndEditsItsVolume) {
  EditorCommands f = EditorCommands::open(std::string(PROSTATESIM_SOURCE_DIR) + "/config/bladder_filling.yaml");
  ASSERT_TRUE(f.doc().valid());
  const Model& m = *f.doc().model();
  const int b = m.find_component("bladder");
  ASSERT_GE(b, 0);
  const double rest_ml = 1e6 * m.surfaces.at(static_cast<size_t>(m.components[static_cast<size_t>(b)].surface)).rest_volume;
  std::vector<FillSegmentView> segs = f.fill_segments();
  ASSERT_EQ(segs.size(), 1u);
  EXPECT_EQ(segs[0].kind, FillSpec::Factor);
  EXPECT_EQ(segs[0].key, "filling.schedule[0].target_factor");
  EXPECT_STREQ(segs[0].label, "volume [x rest]");
  EXPECT_DOUBLE_EQ(segs[0].value, 2.0);
  ASSERT_TRUE(std::isfinite(segs[0].volume_ml));
  EXPECT_NEAR(segs[0].volume_ml, 2.0 * rest_ml, 1e-9 * rest_ml);
  EXPECT_NEAR(segs[0].rest_ml, rest_ml, 1e-9 * rest_ml);
  std::printf("bladder_filling.yaml segment 0: factor %.3g = %.2f ml (rest %.2f ml)\n", segs[0].value, segs[0].volume_ml, rest_ml);

  // the volume in ml on a factor segment: written as the factor (no target_ml beside it)
  const EditResult r = f.set_fill_target_ml(0, 1.5 * rest_ml);
  ASSERT_TRUE(r.ok) << r.issue->field << ": " << r.issue->message;
  EXPECT_TRUE(f.doc().value_text("filling.schedule[0].target_ml").empty());
  EXPECT_NEAR(std::strtod(f.doc().value_text("filling.schedule[0].target_factor").c_str(), nullptr), 1.5, 1e-5);
  segs = f.fill_segments();
  EXPECT_NEAR(segs[0].volume_ml, 1.5 * rest_ml, 1e-5 * rest_ml);
  ASSERT_TRUE(f.spec()->filling.has_value());
  EXPECT_EQ(f.spec()->filling->schedule[0].kind, FillSpec::Factor);
  // the factor field itself, and a refusal next to it
  ASSERT_TRUE(f.set_fill_value(0, 3.0).ok);
  EXPECT_DOUBLE_EQ(f.fill_segments()[0].value, 3.0);
  const EditResult bad = f.set_fill_value(0, -1.0);
  ASSERT_FALSE(bad.ok);
  EXPECT_NE(bad.issue->field.find("filling.schedule[0]"), std::string::npos) << bad.issue->field;
  // a rate segment shows its rate and refuses a volume
  ASSERT_TRUE(f.doc().set("filling.schedule[0]", "{component: bladder, rate_ml_s: 2, ramp_s: [0.5, 2.5]}").ok);
  segs = f.fill_segments();
  EXPECT_EQ(segs[0].key, "filling.schedule[0].rate_ml_s");
  EXPECT_DOUBLE_EQ(segs[0].value, 2.0);
  EXPECT_TRUE(std::isnan(segs[0].volume_ml));
  EXPECT_FALSE(f.set_fill_target_ml(0, 100).ok);
}

// save -> open gives the same compiled scenario (model hash), comments kept; a failed save
// leaves the file intact.
TEST(EditorCommands, SaveThenOpenGivesTheSameModelHash) {
  const fs::path d = fs::temp_directory_path() / ("ps_editor_save_" + std::to_string(::getpid()));
  fs::create_directories(d);
  const fs::path file = d / "block.yaml";
  std::ofstream(file) << "# exercise 3\n" << block_scene();
  EditorCommands c = EditorCommands::open(file.string());
  ASSERT_TRUE(c.add_lesion("lesion_b", "tissue", Vec3(6, 0, -12), 3).ok);
  ASSERT_TRUE(c.set_material("tissue", "damping_1_s", 25).ok);
  c.save();
  const EditorCommands again = EditorCommands::open(file.string());
  EXPECT_EQ(again.doc().model_hash(), c.doc().model_hash());
  EXPECT_EQ(again.doc().text().rfind("# exercise 3\n", 0), 0u);
  const std::string saved = again.doc().text();
  EXPECT_THROW(c.save((d / "no_such_dir" / "x.yaml").string()), std::exception);
  EXPECT_EQ(again.doc().text(), saved);
  fs::remove_all(d);
}

// A case's lesions from a seed: placed by the command, listed as seeded, and moved one by one
// after they become sphere tags that keep exactly their particles (one undo step back).
TEST(EditorCommands, SeededLesionsAreShownAndMovedAsTags) {
  const std::string path = std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml";
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EditorCommands c{ScenarioDocument(ss.str(), path)};
  ASSERT_TRUE(c.doc().valid()) << c.doc().error()->message;
  const EditResult placed = c.place_lesions(2, 7, "peripheral", 8.0);
  ASSERT_TRUE(placed.ok) << placed.issue->field << ": " << placed.issue->message;
  ASSERT_TRUE(c.spec()->lesions.has_value());
  const std::string seeded_text = c.doc().text();
  std::vector<RegionView> seeded;
  for (const RegionView& r : c.regions())
    if (r.seeded) seeded.push_back(r);
  ASSERT_EQ(seeded.size(), 2u);
  EXPECT_EQ(seeded[0].tag, "lesion_1");
  EXPECT_TRUE(seeded[0].lesion);
  EXPECT_DOUBLE_EQ(seeded[0].size_mm.x(), 4.0);
  auto members = [&](const std::string& tag) {
    const Model& m = *c.doc().model();
    const int t = m.find_tag(tag);
    std::vector<int> out;
    for (int p = 0; p < m.particle_count(); ++p)
      if (t >= 0 && (m.particle_tags[p] >> t & 1u)) out.push_back(p);
    return out;
  };
  const std::vector<int> second = members("lesion_2");
  ASSERT_FALSE(second.empty());
  const EditResult moved = c.move_region("lesion_1", seeded[0].center_mm + Vec3(0, 0, 2));
  ASSERT_TRUE(moved.ok) << moved.issue->field << ": " << moved.issue->message;
  EXPECT_FALSE(c.spec()->lesions.has_value()) << "the seeded lesions became tags";
  EXPECT_EQ(c.doc().text().find("\nlesions:"), std::string::npos);
  EXPECT_EQ(members("lesion_2"), second) << "a lesion not moved keeps exactly its particles";
  int tags = 0;
  for (const RegionView& r : c.regions()) {
    EXPECT_FALSE(r.seeded) << r.tag;
    if (r.tag == "lesion_1") {
      ++tags;
      EXPECT_NEAR((r.center_mm - seeded[0].center_mm - Vec3(0, 0, 2)).norm(), 0.0, 1e-9);
    }
    if (r.tag == "lesion_2") ++tags;
  }
  EXPECT_EQ(tags, 2);
  ASSERT_TRUE(c.undo());
  EXPECT_EQ(c.doc().text(), seeded_text) << "turning into tags and the move are one undo step";
}

}  // namespace
}  // namespace ps::editor
