// The scenario editor's core (issue 13): a scenario file held as its original text, edited by key
// path in place so that key order, comments, anchors and formatting of everything not edited stay
// as the instructor wrote them (yaml-cpp would drop comments on re-emitting; here yaml-cpp only
// locates the value through its node marks, and the text of that value is replaced).
//
// Key paths name the file's keys in file units: "materials.prostate.young_kpa",
// "tags[lesion].region.ellipsoid.center_mm", "needles.instruments[biopsy_1].target_mm",
// "needles.instruments[0].script", "probe.pose.insertion_mm", "filling.schedule[0].rate_ml_s".
// A list item is chosen by index [i] or by the value of its `name:` key [name]. A key missing
// from an existing mapping is added (in a {flow} mapping before its '}', in a block mapping as a
// new line at the mapping's indentation).
//
// Every edit is validated before it is kept; a refused edit leaves the document unchanged and
// says which field and why:
//  * the scenario parser's own checks (negative stiffness, unknown keys, bad types...);
//  * compile checks (degenerate geometry), and the instruments' own checks when built (needle
//    paths, the probe's start pose in the rectum and out of bone, the filled organ's volumes);
//  * a needle target_mm outside every organ (no tissue holds it);
//  * overlapping lesions: two tags whose role is lesion (Model::tag_roles) whose regions share particles or
//    volume;
//  * a needle path through bone: the segment from start_mm to the deepest planned depth crosses
//    the surface of a rigid component.
// Undo / redo walk the accepted texts. save() writes atomically (temp + rename): a failed save
// leaves the file on disk as it was. A file that is invalid when opened (edited by hand) opens
// with its error in error(), not an exception, so an editor can show it.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/model/model.h"
#include "engine/spec/scenario_spec.h"
#include "engine/util/vec.h"

namespace ps {

struct DocumentIssue {
  std::string field;               // key path of the field at fault ("" when global)
  int line = 0;                    // 1-based line in the text, 0 unknown
  std::string message;
};

struct EditResult {
  bool ok = false;
  std::optional<DocumentIssue> issue;  // why it was refused
};

class ScenarioDocument {
 public:
  // Reads the file (std::runtime_error when it cannot be read); a scenario error is kept.
  static ScenarioDocument open(const std::string& path);
  ScenarioDocument(std::string text, std::string path);

  const std::string& text() const { return text_; }
  const std::string& path() const { return path_; }
  bool valid() const { return !issue_.has_value(); }
  const std::optional<DocumentIssue>& error() const { return issue_; }
  // The parsed and compiled scenario (null while invalid).
  const ScenarioSpec* spec() const { return spec_ ? spec_.get() : nullptr; }
  std::shared_ptr<const Model> model() const { return model_; }
  uint64_t model_hash() const { return hash_; }

  // Sets the value at `key_path` to `yaml_value` (YAML text in file units: "55", "[9, -7, 2]").
  EditResult set(const std::string& key_path, const std::string& yaml_value);
  EditResult set_number(const std::string& key_path, double value);
  EditResult set_vec3(const std::string& key_path, const Vec3& value);
  // Appends an item (YAML text, e.g. a flow mapping "{name: b2, start_mm: [0, -20, -7], ...}" or a
  // scalar "62") to the list at `list_path` ("tags", "needles.instruments",
  // "needles.instruments[posterior].seeds_mm"): in a [flow] list before its ']', in a block list
  // as a new "- item" line after its last item at the dashes' indentation. A missing list key is
  // added holding [item]. Validated like set(); undo removes it.
  EditResult add_item(const std::string& list_path, const std::string& yaml_item);
  // Removes the item at `item_path` ("needles.instruments[b2]", "tags[1]", "...seeds_mm[2]"): its
  // text (and the separating comma, or its lines of a block list); the last item of a block list
  // leaves "[]". Validated like set(); undo puts it back as it was.
  EditResult remove_item(const std::string& item_path);
  // Removes a top-level key with its value (its line and the lines indented under it; comments
  // and blank lines after it stay). Validated like set(); undo puts it back.
  EditResult remove_top_key(const std::string& key);
  // Makes the last n accepted edits one undo step (a compound edit, such as seeded lesions turned
  // into tags and then moved). False, changing nothing, when fewer than n edits lie behind the
  // current text or a redo is pending.
  bool merge_last(int n);
  // Number of items of the list at `list_path` (0 when absent or not a list).
  int item_count(const std::string& list_path) const;
  // The current YAML text of a value ("" when absent).
  std::string value_text(const std::string& key_path) const;

  bool can_undo() const { return at_ > 0; }
  bool can_redo() const { return at_ + 1 < history_.size(); }
  bool undo();
  bool redo();
  bool modified() const { return text_ != saved_text_; }

  // Writes the text atomically to `path` ("" = where it came from). Throws std::runtime_error
  // naming the path when it cannot be written (the file on disk is left as it was).
  void save(const std::string& path = "");

 private:
  void load(const std::string& text);    // sets text_, spec_, model_, hash_, issue_
  EditResult accept(std::string next, const std::string& field);  // validate and keep
  std::string text_, path_, saved_text_;
  std::vector<std::string> history_;
  size_t at_ = 0;
  std::unique_ptr<ScenarioSpec> spec_;
  std::shared_ptr<const Model> model_;
  uint64_t hash_ = 0;
  std::optional<DocumentIssue> issue_;
};

// The checks of a compiled scenario beyond the parser's (targets, lesions, needle paths); the
// first problem found, or nothing.
std::optional<DocumentIssue> check_scenario_semantics(const ScenarioSpec& spec, const Model& model);

// Text span [begin, end) of the value at key_path in `text`, or the issue that prevents it
// (exposed for tests).
struct ValueSpan {
  size_t begin = 0, end = 0;
  bool exists = false;             // false: the key is missing, `begin` is where to insert
  std::string insert_prefix, insert_suffix;  // text around "key: value" for an insertion
};
ValueSpan locate_value(const std::string& text, const std::string& key_path);
// The text after adding / removing a list item (InputError naming the path when it cannot).
std::string text_with_item_added(const std::string& text, const std::string& list_path, const std::string& yaml_item);
std::string text_with_item_removed(const std::string& text, const std::string& item_path);

}  // namespace ps
