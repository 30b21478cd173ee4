#include "app/editor/editor_commands.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "engine/model/role.h"
#include "engine/scenario/scene_regions.h"
#include "engine/tools/probe/probe_geometry.h"
#include "engine/util/error.h"

namespace ps::editor {

namespace {

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string vec(const Vec3& v) { return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]"; }

// Round-trips a double: a seeded lesion written as a tag keeps exactly its particles.
std::string exact(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

EditResult refused(const std::string& field, const std::string& msg) {
  EditResult r;
  r.issue = DocumentIssue{field, 0, msg};
  return r;
}


const char* shape_key(RegionSpec::Kind k) {
  switch (k) {
    case RegionSpec::Sphere: return "sphere";
    case RegionSpec::Ellipsoid: return "ellipsoid";
    case RegionSpec::Box: return "box";
    default: return nullptr;
  }
}

}  // namespace

std::vector<std::string> EditorCommands::organs() const {
  std::vector<std::string> out;
  if (spec())
    for (const ComponentSpec& c : spec()->components) out.push_back(c.name);
  return out;
}

std::string EditorCommands::material_of(const std::string& organ) const {
  if (spec())
    for (const ComponentSpec& c : spec()->components)
      if (c.name == organ) return c.material;
  return {};
}

EditResult EditorCommands::set_material(const std::string& organ, const std::string& field, double value) {
  const std::string m = material_of(organ);
  if (m.empty()) return refused("components[" + organ + "].material", "no organ '" + organ + "' with a material");
  return doc_.set_number("materials." + m + "." + field, value);
}

std::optional<double> EditorCommands::material_value(const std::string& organ, const std::string& field) const {
  const std::string m = material_of(organ);
  if (m.empty()) return std::nullopt;
  const std::string t = doc_.value_text("materials." + m + "." + field);
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end == t.c_str()) return std::nullopt;
  return v;
}

EditResult EditorCommands::set_puncture_weight(const std::string& organ, double n) {
  return doc_.set_number("needles.puncture_n." + organ, n);
}

std::vector<RegionView> EditorCommands::regions() const {
  std::vector<RegionView> out;
  if (!spec()) return out;
  for (const TagSpec& t : spec()->tags) {
    const char* k = shape_key(t.region.kind);
    if (!k) continue;
    RegionView v;
    v.tag = t.name;
    v.key = "tags[" + t.name + "].region." + k;
    v.kind = t.region.kind;
    v.lesion = resolve_role(t.role, t.name, false) == Role::Lesion;
    switch (t.region.kind) {
      case RegionSpec::Sphere: v.center_mm = 1e3 * t.region.center; v.size_mm = Vec3::Constant(1e3 * t.region.radius); break;
      case RegionSpec::Ellipsoid: v.center_mm = 1e3 * t.region.center; v.size_mm = 1e3 * t.region.radii; break;
      default: v.center_mm = 0.5e3 * (t.region.min + t.region.max); v.size_mm = 0.5e3 * (t.region.max - t.region.min); break;
    }
    out.push_back(v);
  }
  if (spec()->lesions && spec()->prostate_zones && doc_.model()) {
    try {
      const std::vector<Vec3> centres = anatomy::seeded_lesion_centres(*spec(), *doc_.model());
      for (size_t k = 0; k < centres.size(); ++k) {
        RegionView v;
        v.tag = "lesion_" + std::to_string(k + 1);
        v.key = "lesions";
        v.kind = RegionSpec::Sphere;
        v.center_mm = 1e3 * centres[k];
        v.size_mm = Vec3::Constant(0.5e3 * spec()->lesions->diameter);
        v.lesion = v.seeded = true;
        out.push_back(v);
      }
    } catch (const InputError&) {  // a compiled document places them; nothing to show otherwise
    }
  }
  return out;
}

EditResult EditorCommands::place_lesions(int count, int seed, const std::string& zone, double diameter_mm) {
  if (!spec() || !spec()->prostate_zones) return refused("lesions", "lesions are placed in a prostate zone: give prostate_zones first");
  return doc_.set("lesions", "{count: " + std::to_string(count) + ", seed: " + std::to_string(seed) + ", zone: " + zone +
                                 ", diameter_mm: " + num(diameter_mm) + "}");
}

EditResult EditorCommands::lesions_to_tags() {
  if (!spec() || !spec()->lesions) return refused("lesions", "the scenario places no lesions from a seed");
  std::vector<RegionView> seeded;
  for (const RegionView& v : regions())
    if (v.seeded) seeded.push_back(v);
  if (seeded.empty()) return refused("lesions", "the seeded lesions could not be placed: fix the scenario first");
  const std::string gland = spec()->prostate_zones->component;
  EditResult r = doc_.remove_top_key("lesions");
  if (!r.ok) return r;
  int edits = 1;
  for (const RegionView& v : seeded) {
    r = doc_.add_item("tags", "{name: " + v.tag + ", component: " + gland + ", region: {sphere: {center_mm: [" + exact(v.center_mm.x()) +
                                  ", " + exact(v.center_mm.y()) + ", " + exact(v.center_mm.z()) + "], radius_mm: " + exact(v.size_mm.x()) + "}}}");
    if (!r.ok) {  // leave the document as it was
      for (int i = 0; i < edits; ++i) doc_.undo();
      return r;
    }
    ++edits;
  }
  doc_.merge_last(edits);
  return r;
}

EditResult EditorCommands::move_region(const std::string& tag, const Vec3& c) {
  for (const RegionView& v : regions()) {
    if (v.tag != tag) continue;
    if (v.seeded) {  // the seeded lesions become tags, then this one moves: one undo step
      EditResult r = lesions_to_tags();
      if (!r.ok) return r;
      r = move_region(tag, c);
      if (r.ok) doc_.merge_last(2);
      else doc_.undo();
      return r;
    }
    if (v.kind == RegionSpec::Box) {
      // a box moves as a whole: both corners in one edit (one undo step)
      const std::string b = "{min_mm: " + vec(c - v.size_mm) + ", max_mm: " + vec(c + v.size_mm) + "}";
      return doc_.set(v.key, b);
    }
    return doc_.set_vec3(v.key + ".center_mm", c);
  }
  return refused("tags[" + tag + "]", "no tag '" + tag + "' with a sphere, ellipsoid or box region");
}

EditResult EditorCommands::resize_region(const std::string& tag, const Vec3& s) {
  for (const RegionView& v : regions()) {
    if (v.tag != tag) continue;
    if (s.minCoeff() <= 0.0) return refused(v.key, "sizes must be > 0 mm");
    if (v.seeded) {
      EditResult r = lesions_to_tags();
      if (!r.ok) return r;
      r = resize_region(tag, s);
      if (r.ok) doc_.merge_last(2);
      else doc_.undo();
      return r;
    }
    switch (v.kind) {
      case RegionSpec::Sphere: return doc_.set_number(v.key + ".radius_mm", s.x());
      case RegionSpec::Ellipsoid: return doc_.set_vec3(v.key + ".radii_mm", s);
      default: return doc_.set(v.key, "{min_mm: " + vec(v.center_mm - s) + ", max_mm: " + vec(v.center_mm + s) + "}");
    }
  }
  return refused("tags[" + tag + "]", "no tag '" + tag + "' with a sphere, ellipsoid or box region");
}

EditResult EditorCommands::add_lesion(const std::string& name, const std::string& organ, const Vec3& c, double r) {
  if (r <= 0.0) return refused("tags", "the lesion radius must be > 0 mm");
  return doc_.add_item("tags", "{name: " + name + ", component: " + organ + ", region: {sphere: {center_mm: " + vec(c) +
                                   ", radius_mm: " + num(r) + "}}}");
}

EditResult EditorCommands::remove_tag(const std::string& tag) {
  for (const RegionView& v : regions()) {
    if (v.tag != tag || !v.seeded) continue;
    EditResult r = lesions_to_tags();  // the others stay where the seed put them
    if (!r.ok) return r;
    r = doc_.remove_item("tags[" + tag + "]");
    if (r.ok) doc_.merge_last(2);
    else doc_.undo();
    return r;
  }
  return doc_.remove_item("tags[" + tag + "]");
}

std::string EditorCommands::needle_key(const std::string& needle) const { return "needles.instruments[" + needle + "]"; }

EditResult EditorCommands::set_needle_target(const std::string& needle, const Vec3& t) {
  return doc_.set_vec3(needle_key(needle) + ".target_mm", t);
}

std::vector<FillSegmentView> EditorCommands::fill_segments() const {
  std::vector<FillSegmentView> out;
  const ScenarioSpec* s = spec();
  if (!s || !s->filling) return out;
  const std::shared_ptr<const Model> m = doc_.model();
  for (size_t i = 0; i < s->filling->schedule.size(); ++i) {
    const FillSpec& f = s->filling->schedule[i];
    FillSegmentView v;
    v.index = static_cast<int>(i);
    v.component = f.component;
    v.kind = f.kind;
    v.t0 = f.t0;
    v.t1 = f.t1;
    v.rest_ml = NAN;
    if (m) {
      const int c = m->find_component(f.component);
      const int si = c >= 0 ? m->components[static_cast<size_t>(c)].surface : -1;
      if (si >= 0) v.rest_ml = 1e6 * m->surfaces[static_cast<size_t>(si)].rest_volume;
    }
    const std::string k = "filling.schedule[" + std::to_string(i) + "]";
    switch (f.kind) {  // the spec's value in SI units; the field's in the file's
      case FillSpec::Rate:
        v.key = k + ".rate_ml_s";
        v.label = "fill rate [ml/s]";
        v.value = f.value * 1e6;
        v.volume_ml = NAN;
        break;
      case FillSpec::Target:
        v.key = k + ".target_ml";
        v.label = "volume [ml]";
        v.value = f.value * 1e6;
        v.volume_ml = v.value;
        break;
      case FillSpec::Factor:
        v.key = k + ".target_factor";
        v.label = "volume [x rest]";
        v.value = f.value;
        v.volume_ml = f.value * v.rest_ml;
        break;
    }
    out.push_back(std::move(v));
  }
  return out;
}

EditResult EditorCommands::set_fill_value(int i, double v) {
  const std::vector<FillSegmentView> segs = fill_segments();
  if (i < 0 || i >= static_cast<int>(segs.size())) return refused("filling.schedule", "no filling segment " + std::to_string(i));
  return doc_.set_number(segs[static_cast<size_t>(i)].key, v);
}

EditResult EditorCommands::set_fill_target_ml(int i, double ml) {
  const std::vector<FillSegmentView> segs = fill_segments();
  const std::string k = "filling.schedule[" + std::to_string(i) + "]";
  if (i >= 0 && i < static_cast<int>(segs.size())) {
    const FillSegmentView& v = segs[static_cast<size_t>(i)];
    if (v.kind == FillSpec::Rate) return refused(v.key, "this segment is given as a fill rate, not a volume");
    if (v.kind == FillSpec::Factor) {
      if (!(v.rest_ml > 0.0)) return refused(v.key, "the organ's rest volume is unknown: fix the scenario first");
      return doc_.set_number(v.key, ml / v.rest_ml);
    }
  }
  return doc_.set_number(k + ".target_ml", ml);
}
EditResult EditorCommands::set_fill_rate_ml_s(int i, double v) {
  return doc_.set_number("filling.schedule[" + std::to_string(i) + "].rate_ml_s", v);
}
EditResult EditorCommands::set_max_fill_rate_ml_s(double v) { return doc_.set_number("filling.max_rate_ml_s", v); }

EditResult EditorCommands::add_filling() {
  if (!spec() || !doc_.model()) return refused("filling", "the scenario is invalid: fix it first");
  if (spec()->filling) return refused("filling", "the scenario has a filling: section already");
  const Model& m = *doc_.model();
  int pick = -1;
  for (size_t c = 0; c < m.components.size(); ++c) {
    const int si = m.components[c].surface;
    if (si < 0 || !m.surfaces[static_cast<size_t>(si)].volume_constrained) continue;
    if (pick < 0 || m.components[c].role == Role::Bladder) pick = static_cast<int>(c);
  }
  if (pick < 0) return refused("filling", "no organ has a volume constraint (incompressible: true): nothing can be filled");
  const double rest_ml = 1e6 * m.surfaces[static_cast<size_t>(m.components[static_cast<size_t>(pick)].surface)].rest_volume;
  char ml[64];
  std::snprintf(ml, sizeof ml, "%.10g", rest_ml);  // the rest volume itself, not a rounding of it
  return doc_.set("filling", "{max_rate_ml_s: 5, schedule: [{component: " + m.components[static_cast<size_t>(pick)].name +
                                 ", target_ml: " + ml + ", ramp_s: [0, 1]}]}");
}

EditResult EditorCommands::add_probe(const std::string& mount) {
  if (mount != "needle_guide" && mount != "template" && mount != "none")
    return refused("probe", "mount '" + mount + "' is not needle_guide, template or none");
  if (!spec()) return refused("probe", "the scenario is invalid: fix it first");
  if (spec()->probe) return refused("probe", "the scenario has a probe: section already");
  std::string v = "{radius_mm: 10, length_mm: 45, entry_mm: [0, -30.6, -32], axis: [0, 0, 1], anterior: [0, 1, 0], pose: {insertion_mm: 40}";
  if (mount == "needle_guide") v += ", needle_guide: {angle_deg: 20, back_mm: 15}";
  if (mount == "template") v += ", template: {distance_mm: 30, pitch_mm: 5, cols: 13, rows: 13, first_row_mm: 10}";
  return doc_.set("probe", v + "}");
}

EditResult EditorCommands::set_probe_pose(const std::string& field, double v) {
  if (field != "insertion_mm" && field != "roll_deg" && field != "tilt_deg" && field != "yaw_deg")
    return refused("probe.pose." + field, "not a pose field (insertion_mm, roll_deg, tilt_deg, yaw_deg)");
  if (!spec() || !spec()->probe) return refused("probe", "the scenario has no probe: section");
  return doc_.set_number("probe.pose." + field, v);
}

EditResult EditorCommands::add_template_needle(const std::string& name, int col, int row, double depth_mm, double time_s) {
  if (!spec() || !spec()->probe || !spec()->probe->has_template) return refused("probe.template", "the probe has no template: section");
  if (depth_mm <= 0.0 || time_s <= 0.0) return refused("needles.instruments", "depth and time must be > 0");
  NeedlePath p;
  try {
    const ProbeSpec& ps = *spec()->probe;
    p = template_hole_path(ps, rectal_frame(ps), ps.pose, col, row);
  } catch (const InputError& e) {
    return refused("needles.instruments", e.what());
  }
  return doc_.add_item("needles.instruments", "{name: " + name + ", preset: brachy_18g, start_mm: " + vec(1e3 * p.entry) +
                                                  ", direction: " + vec(p.direction) + ", script: [[0, 0], [" + num(time_s) + ", " +
                                                  num(depth_mm) + "]]}");
}

EditResult EditorCommands::add_biopsy_core(const std::string& name, const std::string& site, const Vec3& target_mm) {
  if (!spec() || !spec()->probe || !spec()->probe->has_guide) return refused("probe.needle_guide", "the probe has no needle_guide: section");
  const ProbeSpec& ps = *spec()->probe;
  const NeedlePath p = biopsy_guide_path(ps, probe_frame(ps, rectal_frame(ps), ps.pose));
  return doc_.add_item("needles.instruments", "{name: " + name + ", preset: biopsy_18g, start_mm: " + vec(1e3 * p.entry) +
                                                  ", direction: " + vec(p.direction) + ", gun: {}, target_mm: " + vec(target_mm) +
                                                  ", planned_site: " + site + "}");
}

EditResult EditorCommands::add_seed(const std::string& needle, double depth_mm) {
  return doc_.add_item(needle_key(needle) + ".seeds_mm", num(depth_mm));
}

EditResult EditorCommands::remove_seed(const std::string& needle, int i) {
  return doc_.remove_item(needle_key(needle) + ".seeds_mm[" + std::to_string(i) + "]");
}

EditResult EditorCommands::remove_needle(const std::string& needle) { return doc_.remove_item(needle_key(needle)); }

EditResult EditorCommands::set_needle_depth(const std::string& needle, double depth_mm, double time_s) {
  return doc_.set(needle_key(needle) + ".script", "[[0, 0], [" + num(time_s) + ", " + num(depth_mm) + "]]");
}

Scene EditorCommands::preview_scene() const {
  if (!spec()) throw InputError(doc_.path(), doc_.error() ? doc_.error()->line : 0, doc_.error() ? doc_.error()->field : "",
                                doc_.error() ? doc_.error()->message : "invalid scenario");
  return build_scene(*spec());
}

void FieldErrors::note(const std::string& widget_key, const EditResult& r) {
  if (r.ok) {
    messages_.erase(widget_key);
    // an accepted edit settles the messages it named
    for (auto it = messages_.begin(); it != messages_.end();) {
      const std::string& k = it->first;
      const bool below = k.rfind(widget_key, 0) == 0 && (k.size() == widget_key.size() || k[widget_key.size()] == '.' || k[widget_key.size()] == '[');
      it = below ? messages_.erase(it) : std::next(it);
    }
    return;
  }
  const std::string msg = r.issue ? r.issue->message : "refused";
  messages_[widget_key] = msg;
  if (r.issue && !r.issue->field.empty()) messages_[r.issue->field] = msg;
}

std::string FieldErrors::for_key(const std::string& key) const {
  auto it = messages_.find(key);
  if (it != messages_.end()) return it->second;
  // a key below it, or the item it belongs to: the prefix must end at a '.' or '['
  auto under = [](const std::string& a, const std::string& b) {
    return a.size() > b.size() && a.rfind(b, 0) == 0 && (a[b.size()] == '.' || a[b.size()] == '[');
  };
  for (const auto& [k, m] : messages_)
    if (under(k, key) || under(key, k)) return m;
  return {};
}

}  // namespace ps::editor
