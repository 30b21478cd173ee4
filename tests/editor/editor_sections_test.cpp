// Adding a missing `filling:` or `probe:` section through the editor's command path
// (EditorCommands::add_filling / add_probe): the biopsy scene gets a bladder filling held at the
// bladder's rest volume, the bladder-filling scene a TRUS probe with a biopsy guide; each is
// validated like any edit, then edited with the existing fields (fill target and rate, probe
// pose), saved, and opened again: the same compiled scenario (model hash, filling and probe
// sections) and a runnable scene with the new instrument. A second add is refused naming the
// section; undo removes it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "app/editor/editor_commands.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/filling/filling.h"

namespace ps::editor {
namespace {

namespace fs = std::filesystem;

class EditorSections : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ps_editor_sections_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "config");
    // the scenes refer to ../assets/anatomy: the copies sit beside a link to the real assets
    fs::create_directory_symlink(fs::path(PROSTATESIM_SOURCE_DIR) / "assets", dir_ / "assets");
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string copy(const std::string& name) {
    const fs::path p = dir_ / "config" / name;
    fs::copy_file(fs::path(PROSTATESIM_SOURCE_DIR) / "config" / name, p);
    return p.string();
  }
  fs::path dir_;
};

TEST_F(EditorSections, AddFillingSaveAndLoadGiveTheSameCompiledScenario) {
  const std::string file = copy("biopsy.yaml");
  EditorCommands c = EditorCommands::open(file);
  ASSERT_TRUE(c.doc().valid()) << c.doc().error()->message;
  ASSERT_FALSE(c.spec()->filling.has_value());
  const EditResult r = c.add_filling();
  ASSERT_TRUE(r.ok) << r.issue->message;
  ASSERT_TRUE(c.spec()->filling.has_value());
  const FillingSpec& f = *c.spec()->filling;
  ASSERT_EQ(f.schedule.size(), 1u);
  EXPECT_EQ(f.schedule[0].component, "bladder");
  EXPECT_NEAR(f.max_rate, 5e-6, 1e-15);  // 5 ml/s [m^3/s]
  // held at its rest volume: the bladder's rest volume in the compiled model
  const Model& m0 = *c.doc().model();
  const int b = m0.find_component("bladder");
  ASSERT_GE(b, 0);
  const double rest = m0.surfaces.at(static_cast<size_t>(m0.components[static_cast<size_t>(b)].surface)).rest_volume;
  EXPECT_NEAR(f.schedule[0].value, rest, 1e-6 * rest);
  std::printf("added filling: bladder rest volume %.2f ml\n", rest * 1e6);
  // a second one is refused naming the section; the fields edit it
  const EditResult again = c.add_filling();
  ASSERT_FALSE(again.ok);
  EXPECT_EQ(again.issue->field, "filling");
  ASSERT_TRUE(c.set_fill_target_ml(0, 1.5 * rest * 1e6).ok);
  // refused when the volume leaves 0.1..10x rest (the filling tool's own check, next to the field)
  const EditResult too_big = c.set_fill_target_ml(0, 20 * rest * 1e6);
  ASSERT_FALSE(too_big.ok);
  EXPECT_NE(too_big.issue->field.find("filling.schedule[0]"), std::string::npos) << too_big.issue->field;
  const uint64_t hash = c.doc().model_hash();
  const FillingSpec edited = *c.spec()->filling;
  c.save();
  // opened again: the same compiled scenario
  EditorCommands back = EditorCommands::open(file);
  ASSERT_TRUE(back.doc().valid()) << back.doc().error()->message;
  EXPECT_EQ(back.doc().model_hash(), hash);
  ASSERT_TRUE(back.spec()->filling.has_value());
  EXPECT_EQ(back.spec()->filling->max_rate, edited.max_rate);
  ASSERT_EQ(back.spec()->filling->schedule.size(), 1u);
  EXPECT_EQ(back.spec()->filling->schedule[0].value, edited.schedule[0].value);
  EXPECT_EQ(back.spec()->filling->schedule[0].t1, edited.schedule[0].t1);
  const Scene sc = back.preview_scene();
  EXPECT_GE(sc.tools.index<FillingTool>(), 0) << "no filling tool in the scene built from the saved file";
  // the file keeps everything else: the comments of the original are still there
  EXPECT_NE(back.doc().text().find("# an example lesion"), std::string::npos);
  // undo (in the first document) removes the section again
  while (c.spec()->filling) ASSERT_TRUE(c.undo());
}

TEST_F(EditorSections, AddProbeSaveAndLoadGiveTheSameCompiledScenario) {
  const std::string file = copy("bladder_filling.yaml");
  EditorCommands c = EditorCommands::open(file);
  ASSERT_TRUE(c.doc().valid()) << c.doc().error()->message;
  ASSERT_FALSE(c.spec()->probe.has_value());
  // without a probe the pose fields are refused, naming the section
  EXPECT_EQ(c.set_probe_pose("insertion_mm", 45).issue->field, "probe");
  EXPECT_FALSE(c.add_probe("stepper").ok);
  const EditResult r = c.add_probe("needle_guide");
  ASSERT_TRUE(r.ok) << r.issue->message;
  ASSERT_TRUE(c.spec()->probe.has_value());
  EXPECT_TRUE(c.spec()->probe->has_guide);
  EXPECT_NEAR(c.spec()->probe->pose.insertion, 0.040, 1e-12);
  EXPECT_EQ(c.add_probe().issue->field, "probe");
  // the pose field now edits it; a pose out of the rectum is refused next to probe.pose
  ASSERT_TRUE(c.set_probe_pose("insertion_mm", 45).ok);
  const EditResult out = c.set_probe_pose("tilt_deg", 44);
  if (!out.ok) EXPECT_NE(out.issue->field.find("probe"), std::string::npos) << out.issue->field;
  else ASSERT_TRUE(c.undo());
  const uint64_t hash = c.doc().model_hash();
  const ProbeSpec p = *c.spec()->probe;
  c.save();
  EditorCommands back = EditorCommands::open(file);
  ASSERT_TRUE(back.doc().valid()) << back.doc().error()->message;
  EXPECT_EQ(back.doc().model_hash(), hash);
  ASSERT_TRUE(back.spec()->probe.has_value());
  EXPECT_EQ(back.spec()->probe->pose.insertion, p.pose.insertion);
  EXPECT_NEAR(back.spec()->probe->pose.insertion, 0.045, 1e-12);
  EXPECT_EQ(back.spec()->probe->entry, p.entry);
  EXPECT_EQ(back.spec()->probe->radius, p.radius);
  EXPECT_TRUE(back.spec()->probe->has_guide);
  const Scene sc = back.preview_scene();
  EXPECT_GE(sc.tools.index<ProbeTool>(), 0) << "no probe in the scene built from the saved file";
  EXPECT_GE(sc.tools.index<FillingTool>(), 0);
}

}  // namespace
}  // namespace ps::editor
