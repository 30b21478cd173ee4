// The instructor editor's commands (issue 13), testable without a window: each is one edit of
// the ScenarioDocument (engine/scenario/scenario_document.h), validated, undoable, in the file's
// units (mm, kPa, ml, degrees). The window (editor_window.cpp) only calls these; tests call the
// same functions, so "an edit through the editor's command path" is this class.
//
// Field names for messages: every refused edit returns the DocumentIssue whose `field` is the key
// path at fault; the window shows the message beside the widget bound to that key path
// (FieldErrors below).
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/scenario/scenario_document.h"
#include "engine/sim/scene.h"

namespace ps::editor {

// One tag with a bounded region (lesion, target zone) as the editor shows it [mm].
struct RegionView {
  std::string tag;                 // tag name
  std::string key;                 // key path of the region's shape: "tags[lesion].region.ellipsoid"
  RegionSpec::Kind kind = RegionSpec::All;
  Vec3 center_mm = Vec3::Zero();
  Vec3 size_mm = Vec3::Zero();     // radii (ellipsoid), radius x3 (sphere), half-extents (box)
  bool lesion = false;             // named *lesion* / *tumo*
  bool seeded = false;             // placed by `lesions:` from its seed (key "lesions"): moving or
                                   // resizing it first turns the seeded lesions into tags
};

// One segment of filling.schedule as the editor shows it: the field the file gives it by (a rate,
// a volume in ml or a factor of the organ's rest volume; filling_parse.h) and, for a volume, what
// it is in ml. A segment given as target_factor shows and edits its factor; it has no target_ml.
struct FillSegmentView {
  int index = 0;
  std::string component;
  FillSpec::Kind kind = FillSpec::Rate;
  std::string key;                 // key path of its field: "filling.schedule[0].target_factor"
  const char* label = "";          // "fill rate [ml/s]", "volume [ml]", "volume [x rest]"
  double value = 0.0;              // that field's value, in the file's unit (ml/s, ml, factor)
  double volume_ml = 0.0;          // Target, Factor: the target volume [ml] (factor x rest); Rate: NAN
  double rest_ml = 0.0;            // the organ's rest volume [ml] (NAN when the model is not built)
  double t0 = 0.0, t1 = 0.0;       // ramp_s [s]
};

class EditorCommands {
 public:
  explicit EditorCommands(ScenarioDocument doc) : doc_(std::move(doc)) {}
  static EditorCommands open(const std::string& path) { return EditorCommands(ScenarioDocument::open(path)); }

  ScenarioDocument& doc() { return doc_; }
  const ScenarioDocument& doc() const { return doc_; }
  const ScenarioSpec* spec() const { return doc_.spec(); }

  // --- organs and materials ---
  std::vector<std::string> organs() const;                 // component names
  std::string material_of(const std::string& organ) const; // the material key of the organ
  // field: young_kpa, damping_1_s, density_kg_m3, k_c_n, k_f_n
  EditResult set_material(const std::string& organ, const std::string& field, double value);
  std::optional<double> material_value(const std::string& organ, const std::string& field) const;
  EditResult set_puncture_weight(const std::string& organ, double newtons);  // needles.puncture_n.<organ>

  // --- lesions and targets ---
  std::vector<RegionView> regions() const;                 // tags with a sphere, ellipsoid or box
  EditResult move_region(const std::string& tag, const Vec3& center_mm);
  EditResult resize_region(const std::string& tag, const Vec3& size_mm);  // sphere: size.x
  EditResult add_lesion(const std::string& name, const std::string& organ, const Vec3& center_mm, double radius_mm);
  EditResult remove_tag(const std::string& tag);
  // A case's lesions from a seed: `lesions: {count, seed, zone, diameter_mm}` (the gland's
  // prostate_zones zone tag, e.g. "peripheral"); regions() then lists them as seeded.
  EditResult place_lesions(int count, int seed, const std::string& zone, double diameter_mm);
  // The seeded lesions as sphere tags lesion_1..n (same particles: the sphere of the diameter
  // around each drawn centre) in place of `lesions:`, so they can be moved one by one; one undo step.
  EditResult lesions_to_tags();
  EditResult set_needle_target(const std::string& needle, const Vec3& target_mm);

  // --- bladder filling: segment i of filling.schedule ---
  std::vector<FillSegmentView> fill_segments() const;
  // Sets the segment's own field (fill_segments()[i].key) to v in its unit.
  EditResult set_fill_value(int segment, double v);
  // The target volume in ml: written as target_ml, or, for a segment given as target_factor, as
  // the factor ml / rest volume (the file keeps its form). Refused naming the segment's field
  // for a rate segment.
  EditResult set_fill_target_ml(int segment, double ml);
  EditResult set_fill_rate_ml_s(int segment, double ml_s);
  EditResult set_max_fill_rate_ml_s(double ml_s);

  // Adds a `filling:` section to a scenario without one: the bladder (else the first organ with a
  // volume constraint, incompressible: true) held at its rest volume (one segment, target_ml =
  // its rest volume over ramp_s [0, 1]) under the default rate limit (5 ml/s); the instructor then
  // sets the volume and rate with the fields above. Refused naming "filling" when the section
  // exists or no organ can be filled.
  EditResult add_filling();

  // --- probe start pose: insertion_mm, roll_deg, tilt_deg, yaw_deg ---
  EditResult set_probe_pose(const std::string& field, double value);
  // Adds a `probe:` section to a scenario without one: the shipped scenes' TRUS probe (radius
  // 10 mm, length 45 mm, anal entry [0, -30.6, -32] mm of the default anatomy, axis +z, anterior
  // +y, inserted 40 mm) with `mount`: "needle_guide" (biopsy: 20 deg, 15 mm back), "template"
  // (brachytherapy: 13 x 13 holes, 5 mm pitch, 30 mm from the entry) or "none". Validated like any
  // edit (a start pose outside the rectum is refused naming probe.pose). Refused naming "probe"
  // when the section exists.
  EditResult add_probe(const std::string& mount = "needle_guide");

  // --- needle plan ---
  // Brachytherapy: a needle through template hole (col, row) at the probe's start pose, inserted
  // to depth_mm along the hole's path by `time_s` (script [[0, 0], [time_s, depth]]).
  EditResult add_template_needle(const std::string& name, int col, int row, double depth_mm, double time_s = 2.0);
  // Biopsy: a needle along the probe's biopsy guide, aimed at target_mm, labelled with its planned
  // 12-core site ("right mid lateral"), fired by command.
  EditResult add_biopsy_core(const std::string& name, const std::string& planned_site, const Vec3& target_mm);
  EditResult add_seed(const std::string& needle, double depth_mm);
  EditResult remove_seed(const std::string& needle, int index);
  EditResult remove_needle(const std::string& needle);
  EditResult set_needle_depth(const std::string& needle, double depth_mm, double time_s);  // script end point

  // --- undo / redo / save ---
  bool undo() { return doc_.undo(); }
  bool redo() { return doc_.redo(); }
  void save(const std::string& path = "") { doc_.save(path); }

  // Preview: the current document built into a runnable scene (its own Simulation). Throws
  // InputError / CompileError when the document is invalid.
  Scene preview_scene() const;

 private:
  std::string needle_key(const std::string& needle) const;
  ScenarioDocument doc_;
};

// The messages of refused edits, by the key path they name; a widget shows the message of its key
// (or of a key inside it: "tags[2].region" is shown by the tag's widgets).
class FieldErrors {
 public:
  // Records the result of an edit on `widget_key`: refused -> the message at the issue's
  // field (and at widget_key), accepted -> clears widget_key's message.
  void note(const std::string& widget_key, const EditResult& r);
  // The message for a widget bound to `key` ("" none): an issue on key itself, on a key below it
  // or on the item it belongs to.
  std::string for_key(const std::string& key) const;
  void clear() { messages_.clear(); }
  const std::map<std::string, std::string>& all() const { return messages_; }

 private:
  std::map<std::string, std::string> messages_;
};

}  // namespace ps::editor
