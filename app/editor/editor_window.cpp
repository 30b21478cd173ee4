#include "app/editor/editor_window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes (ImGui 1.86 reads keys by GLFW code)
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/editor/editor_commands.h"
#include "app/editor/view_drag.h"
#include "app/window/app_window.h"
#include "engine/realtime/lockstep.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/tool_kind.h"
#include "engine/util/error.h"
#include "render/gl_api.h"
#include "render/render_error.h"
#include "render/renderer.h"

namespace ps::editor {

namespace {

constexpr float kPanel = 440.0f;  // editing panel width [px]
const ImVec4 kRed(1.0f, 0.42f, 0.42f, 1.0f), kDim(0.65f, 0.65f, 0.7f, 1.0f), kHead(0.6f, 0.9f, 1.0f, 1.0f);
const char* kMaterialFields[] = {"young_kpa", "damping_1_s", "density_kg_m3", "k_c_n", "k_f_n"};
const char* kSites[] = {"right base lateral", "right base medial", "right mid lateral", "right mid medial",
                        "right apex lateral", "right apex medial", "left base lateral", "left base medial",
                        "left mid lateral", "left mid medial", "left apex lateral", "left apex medial"};

double number_or(const std::string& t, double fallback) {
  if (t.empty()) return fallback;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  return end == t.c_str() ? fallback : v;
}

struct Preview {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<LockstepRunner> runner;
  std::unique_ptr<render::Renderer> renderer;
  uint64_t model_hash = 0;
  bool running = false;
  std::string error;
};

struct Ui {
  render::OrbitCamera orbit;
  render::RenderOptions ropt;
  int organ = 0;
  char open_path[512] = {};
  char save_as[512] = {};
  char any_key[256] = {};
  char any_value[256] = {};
  char new_lesion[64] = "lesion_2";
  double new_lesion_c[3] = {0, 0, 0};
  double new_lesion_r = 4.0;
  int seed_count = 2, seed_value = 1, seed_zone = 0;
  double seed_diameter = 10.0;
  char new_needle[64] = "t_new";
  int hole[2] = {6, 2};
  double hole_depth = 60.0;
  int site = 2;
  double core_target[3] = {10, -5, 0};
  double seed_depth[64] = {};
  std::string status;              // last save / open message
  bool status_error = false;
  ViewDrag drag;                   // picking and dragging handles in the 3D view (view_drag.h)
  bool orbiting = false;
};

// A number field bound to a key path: Enter applies `apply(value)`; the message of a refused edit
// is shown under it, in red.
template <class F>
void number_field(FieldErrors& errs, const char* label, const std::string& key, double value, F apply, const char* fmt = "%.4g") {
  double v = value;
  ImGui::SetNextItemWidth(150);
  if (ImGui::InputDouble(label, &v, 0.0, 0.0, fmt, ImGuiInputTextFlags_EnterReturnsTrue)) errs.note(key, apply(v));
  const std::string m = errs.for_key(key);
  if (!m.empty()) ImGui::TextColored(kRed, "  %s", m.c_str());
}

template <class F>
void vec_field(FieldErrors& errs, const char* label, const std::string& key, const Vec3& value, F apply) {
  double v[3] = {value.x(), value.y(), value.z()};
  ImGui::SetNextItemWidth(240);
  if (ImGui::InputScalarN(label, ImGuiDataType_Double, v, 3, nullptr, nullptr, "%.3g", ImGuiInputTextFlags_EnterReturnsTrue))
    errs.note(key, apply(Vec3(v[0], v[1], v[2])));
  const std::string m = errs.for_key(key);
  if (!m.empty()) ImGui::TextColored(kRed, "  %s", m.c_str());
}

// Rebuilds the preview scene (and its renderer when the model changed) from the document.
void rebuild(Preview& p, const EditorCommands& c, Ui& ui) {
  p.running = false;
  p.error.clear();
  if (!c.doc().valid()) {
    p.scene.reset();
    p.runner.reset();
    p.renderer.reset();
    p.model_hash = 0;
    return;
  }
  try {
    auto scene = std::make_unique<Scene>(c.preview_scene());
    auto runner = std::make_unique<LockstepRunner>(*scene->sim);
    const bool new_model = !p.renderer || p.model_hash != c.doc().model_hash();
    if (new_model) {
      auto r = std::make_unique<render::Renderer>(render::make_render_scene(scene->spec, *scene->model));
      if (!p.renderer) {
        ui.orbit.target = r->scene().focus;
        ui.orbit.distance = r->scene().extent * 3.0;
      }
      ui.ropt.opacity.clear();
      for (const auto& s : r->scene().surfaces) ui.ropt.opacity.push_back(s.colour.a);
      p.renderer = std::move(r);
    }
    p.runner.reset();
    p.scene = std::move(scene);
    p.runner = std::move(runner);
    p.model_hash = c.doc().model_hash();
  } catch (const std::exception& e) {
    p.error = e.what();
    p.scene.reset();
    p.runner.reset();
    p.renderer.reset();
  }
}

std::string issue_text(const ScenarioDocument& d, const DocumentIssue& i) {
  return d.path() + ":" + std::to_string(i.line) + ": '" + i.field + "': " + i.message;
}

// --- panels ---

void document_panel(std::unique_ptr<EditorCommands>& cmds, FieldErrors& errs, Ui& ui, bool& reopen) {
  ImGui::SetNextItemWidth(300);
  ImGui::InputText("##open", ui.open_path, sizeof ui.open_path);
  ImGui::SameLine();
  if (ImGui::Button("Open")) reopen = true;
  if (!cmds) return;
  EditorCommands& c = *cmds;
  if (ImGui::Button("Save")) {
    try {
      c.save();
      ui.status = "saved " + c.doc().path();
      ui.status_error = false;
    } catch (const std::exception& e) {
      ui.status = e.what();
      ui.status_error = true;
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("Undo") || (ImGui::GetIO().KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Z, false) && !ImGui::GetIO().WantTextInput)) {
    if (c.undo()) errs.clear();
  }
  ImGui::SameLine();
  if (ImGui::Button("Redo") || (ImGui::GetIO().KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Y, false) && !ImGui::GetIO().WantTextInput)) {
    if (c.redo()) errs.clear();
  }
  ImGui::SameLine();
  ImGui::TextColored(kDim, "%s%s", c.doc().modified() ? "modified" : "saved", c.doc().can_undo() ? "" : "");
  ImGui::SetNextItemWidth(240);
  ImGui::InputText("##saveas", ui.save_as, sizeof ui.save_as);
  ImGui::SameLine();
  if (ImGui::Button("Save as") && ui.save_as[0]) {
    try {
      c.save(ui.save_as);
      ui.status = std::string("saved ") + ui.save_as;
      ui.status_error = false;
    } catch (const std::exception& e) {
      ui.status = e.what();
      ui.status_error = true;
    }
  }
  if (!ui.status.empty()) ImGui::TextColored(ui.status_error ? kRed : kDim, "%s", ui.status.c_str());
  if (const auto& e = c.doc().error()) {
    ImGui::TextColored(kRed, "The scenario is invalid:");
    ImGui::PushTextWrapPos(kPanel - 10);
    ImGui::TextColored(kRed, "%s", issue_text(c.doc(), *e).c_str());
    ImGui::PopTextWrapPos();
    ImGui::TextColored(kDim, "Fix it below (any key path), then save.");
  } else {
    ImGui::TextColored(kDim, "model hash %016llx", static_cast<unsigned long long>(c.doc().model_hash()));
  }
}

void any_key_panel(EditorCommands& c, FieldErrors& errs, Ui& ui) {
  ImGui::SetNextItemWidth(250);
  ImGui::InputText("key path", ui.any_key, sizeof ui.any_key);
  if (ImGui::IsItemEdited()) std::snprintf(ui.any_value, sizeof ui.any_value, "%s", c.doc().value_text(ui.any_key).c_str());
  ImGui::SetNextItemWidth(250);
  const bool enter = ImGui::InputText("value", ui.any_value, sizeof ui.any_value, ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  if ((ImGui::Button("Apply") || enter) && ui.any_key[0]) errs.note(ui.any_key, c.doc().set(ui.any_key, ui.any_value));
  const std::string m = errs.for_key(ui.any_key);
  if (ui.any_key[0] && !m.empty()) ImGui::TextColored(kRed, "  %s", m.c_str());
}

void organ_panel(EditorCommands& c, FieldErrors& errs, Ui& ui) {
  const std::vector<std::string> organs = c.organs();
  if (organs.empty()) return;
  ui.organ = std::clamp(ui.organ, 0, static_cast<int>(organs.size()) - 1);
  ImGui::SetNextItemWidth(200);
  if (ImGui::BeginCombo("organ", organs[ui.organ].c_str())) {
    for (int i = 0; i < static_cast<int>(organs.size()); ++i)
      if (ImGui::Selectable(organs[i].c_str(), i == ui.organ)) ui.organ = i;
    ImGui::EndCombo();
  }
  const std::string organ = organs[ui.organ], mat = c.material_of(organ);
  ImGui::TextColored(kDim, "material: %s", mat.c_str());
  for (const char* f : kMaterialFields) {
    const std::string key = "materials." + mat + "." + f;
    number_field(errs, f, key, c.material_value(organ, f).value_or(NAN), [&](double v) { return c.set_material(organ, f, v); });
  }
  if (c.spec() && !c.spec()->needles.needles.empty()) {
    const std::string key = "needles.puncture_n." + organ;
    number_field(errs, "puncture weight [N]", key, number_or(c.doc().value_text(key), NAN),
                 [&](double v) { return c.set_puncture_weight(organ, v); });
  }
}

void lesion_panel(EditorCommands& c, FieldErrors& errs, Ui& ui) {
  for (const RegionView& r : c.regions()) {
    ImGui::PushID(r.tag.c_str());
    const bool sel = ui.drag.selected() == r.tag && ui.drag.selected_kind() == Handle::Region;
    if (ImGui::Selectable((r.tag + (r.seeded ? "  (lesion, from the seed)" : r.lesion ? "  (lesion)" : "")).c_str(), sel))
      ui.drag.select(r.tag, Handle::Region);
    vec_field(errs, "centre [mm]", r.key + ".center_mm", r.center_mm, [&](const Vec3& v) { return c.move_region(r.tag, v); });
    vec_field(errs, r.kind == RegionSpec::Sphere ? "radius [mm]" : r.kind == RegionSpec::Box ? "half size [mm]" : "radii [mm]", r.key,
              r.size_mm, [&](const Vec3& v) { return c.resize_region(r.tag, r.kind == RegionSpec::Sphere ? Vec3::Constant(v.x()) : v); });
    const std::string tag_msg = errs.for_key("tags[" + r.tag + "]");
    if (!tag_msg.empty()) ImGui::TextColored(kRed, "  %s", tag_msg.c_str());
    if (ImGui::SmallButton("remove")) errs.note("tags[" + r.tag + "]", c.remove_tag(r.tag));
    ImGui::PopID();
  }
  ImGui::Separator();
  ImGui::SetNextItemWidth(120);
  ImGui::InputText("##newlesion", ui.new_lesion, sizeof ui.new_lesion);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(60);
  ImGui::InputDouble("r [mm]", &ui.new_lesion_r, 0, 0, "%.3g");
  ImGui::SetNextItemWidth(240);
  ImGui::InputScalarN("centre##new", ImGuiDataType_Double, ui.new_lesion_c, 3, nullptr, nullptr, "%.3g");
  const std::vector<std::string> organs = c.organs();
  if (ImGui::Button("Add lesion") && !organs.empty()) {
    const std::string organ = organs[std::clamp(ui.organ, 0, static_cast<int>(organs.size()) - 1)];
    errs.note("tags", c.add_lesion(ui.new_lesion, organ, Vec3(ui.new_lesion_c[0], ui.new_lesion_c[1], ui.new_lesion_c[2]), ui.new_lesion_r));
  }
  ImGui::SameLine();
  ImGui::TextColored(kDim, "in the organ picked above");
  const std::string m = errs.for_key("tags");
  if (!m.empty()) ImGui::TextColored(kRed, "  %s", m.c_str());
  // a case's lesions from a seed (`lesions:`): an instructor's case library, one seed per case
  ImGui::Separator();
  ImGui::TextUnformatted("Lesions from a seed");
  static const char* kZones[] = {"peripheral", "transition", "anterior"};
  ImGui::SetNextItemWidth(80);
  ImGui::InputInt("count", &ui.seed_count);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(80);
  ImGui::InputInt("seed", &ui.seed_value);
  ImGui::SetNextItemWidth(120);
  ImGui::Combo("zone", &ui.seed_zone, kZones, 3);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(60);
  ImGui::InputDouble("diameter [mm]", &ui.seed_diameter, 0, 0, "%.3g");
  if (ImGui::Button("Place")) errs.note("lesions", c.place_lesions(ui.seed_count, ui.seed_value, kZones[std::clamp(ui.seed_zone, 0, 2)], ui.seed_diameter));
  if (c.spec() && c.spec()->lesions) {
    ImGui::SameLine();
    if (ImGui::Button("As tags (to move one by one)")) errs.note("lesions", c.lesions_to_tags());
  }
  const std::string lm = errs.for_key("lesions");
  if (!lm.empty()) ImGui::TextColored(kRed, "  %s", lm.c_str());
}

// refusal of a section's add button (field errors show at their fields)
void add_error(const FieldErrors& errs, const char* section) {
  const auto it = errs.all().find(section);
  if (it != errs.all().end()) ImGui::TextColored(kRed, "  %s", it->second.c_str());
}

void filling_panel(EditorCommands& c, FieldErrors& errs, Ui&) {
  const ScenarioSpec* s = c.spec();
  if (!s) return;
  if (!s->filling) {  // a missing section is added with defaults (EditorCommands::add_filling)
    if (ImGui::Button("Add bladder filling")) errs.note("filling", c.add_filling());
    add_error(errs, "filling");
    return;
  }
  number_field(errs, "max rate [ml/s]", "filling.max_rate_ml_s", s->filling->max_rate * 1e6, [&](double v) { return c.set_max_fill_rate_ml_s(v); });
  for (const FillSegmentView& v : c.fill_segments()) {
    ImGui::PushID(v.index);
    ImGui::TextColored(kDim, "segment %d: %s, %.3g to %.3g s", v.index, v.component.c_str(), v.t0, v.t1);
    const int i = v.index;
    number_field(errs, v.label, v.key, v.value, [&](double x) { return c.set_fill_value(i, x); });
    if (v.kind == FillSpec::Factor && std::isfinite(v.volume_ml))
      ImGui::TextColored(kDim, "  = %.4g ml (rest volume %.4g ml)", v.volume_ml, v.rest_ml);
    ImGui::PopID();
  }
}

void probe_panel(EditorCommands& c, FieldErrors& errs, Ui&) {
  const ScenarioSpec* s = c.spec();
  if (!s) return;
  if (!s->probe) {  // added with defaults (EditorCommands::add_probe)
    if (ImGui::Button("Add probe (biopsy guide)")) errs.note("probe", c.add_probe("needle_guide"));
    ImGui::SameLine();
    if (ImGui::Button("Add probe (template)")) errs.note("probe", c.add_probe("template"));
    add_error(errs, "probe");
    return;
  }
  ImGui::TextColored(kHead, "Start pose");
  for (const char* f : {"insertion_mm", "roll_deg", "tilt_deg", "yaw_deg"}) {
    const std::string key = std::string("probe.pose.") + f;
    number_field(errs, f, key, number_or(c.doc().value_text(key), 0.0), [&](double v) { return c.set_probe_pose(f, v); });
  }
}

void needle_panel(EditorCommands& c, FieldErrors& errs, Ui& ui) {
  const ScenarioSpec* s = c.spec();
  if (!s) return;
  int idx = 0;
  for (const NeedleSpec& n : s->needles.needles) {
    ImGui::PushID(n.name.c_str());
    const std::string key = "needles.instruments[" + n.name + "]";
    ImGui::TextColored(kHead, "%s", n.name.c_str());
    if (!n.planned_site.empty()) { ImGui::SameLine(); ImGui::TextColored(kDim, "(%s)", n.planned_site.c_str()); }
    ImGui::SameLine();
    if (ImGui::SmallButton("remove")) errs.note(key, c.remove_needle(n.name));
    // no target_mm: the metrics aim at the deepest scripted point; the field starts there
    Vec3 aim = n.target ? Vec3(1e3 * *n.target) : Vec3(1e3 * n.start);
    if (!n.target && !n.script.empty()) aim = 1e3 * (n.start + n.script.back().depth * n.direction.normalized());
    vec_field(errs, n.target ? "target [mm]" : "target [mm] (not set)", key + ".target_mm", aim,
              [&](const Vec3& v) { return c.set_needle_target(n.name, v); });
    if (!n.script.empty()) {
      const double t = n.script.back().t, d = 1e3 * n.script.back().depth;
      number_field(errs, "depth [mm]", key + ".script", d, [&](double v) { return c.set_needle_depth(n.name, v, std::max(t, 0.1)); });
    }
    for (int k = 0; k < static_cast<int>(n.seed_depths.size()); ++k) {
      ImGui::PushID(k);
      ImGui::TextColored(kDim, "  seed %d at %.1f mm", k, 1e3 * n.seed_depths[k]);
      ImGui::SameLine();
      if (ImGui::SmallButton("x")) errs.note(key + ".seeds_mm", c.remove_seed(n.name, k));
      ImGui::PopID();
    }
    if (idx < 64) {
      ImGui::SetNextItemWidth(80);
      ImGui::InputDouble("##seed", &ui.seed_depth[idx], 0, 0, "%.3g");
      ImGui::SameLine();
      if (ImGui::SmallButton("add seed [mm]")) errs.note(key + ".seeds_mm", c.add_seed(n.name, ui.seed_depth[idx]));
      const std::string m = errs.for_key(key + ".seeds_mm");
      if (!m.empty()) ImGui::TextColored(kRed, "  %s", m.c_str());
    }
    const std::string m = errs.for_key(key);
    if (!m.empty()) ImGui::TextColored(kRed, "  %s", m.c_str());
    ImGui::PopID();
    ++idx;
  }
  ImGui::Separator();
  ImGui::SetNextItemWidth(120);
  ImGui::InputText("name##newneedle", ui.new_needle, sizeof ui.new_needle);
  if (s->probe && s->probe->has_template) {
    ImGui::SetNextItemWidth(120);
    ImGui::InputInt2("hole col, row", ui.hole);
    ImGui::SetNextItemWidth(120);
    ImGui::InputDouble("depth [mm]##hole", &ui.hole_depth, 0, 0, "%.3g");
    if (ImGui::Button("Add template needle")) errs.note("needles.instruments", c.add_template_needle(ui.new_needle, ui.hole[0], ui.hole[1], ui.hole_depth));
  }
  if (s->probe && s->probe->has_guide) {
    ImGui::SetNextItemWidth(220);
    ImGui::Combo("planned site", &ui.site, kSites, 12);
    ImGui::SetNextItemWidth(240);
    ImGui::InputScalarN("target##core", ImGuiDataType_Double, ui.core_target, 3, nullptr, nullptr, "%.3g");
    if (ImGui::Button("Add planned core"))
      errs.note("needles.instruments",
                c.add_biopsy_core(ui.new_needle, kSites[ui.site], Vec3(ui.core_target[0], ui.core_target[1], ui.core_target[2])));
  }
  const std::string m = errs.for_key("needles.instruments");
  if (!m.empty()) ImGui::TextColored(kRed, "  %s", m.c_str());
}

// The editor's section of each instrument kind (engine/tools/tool_kind.h), in the order shown; a
// new kind adds its panel function and one line here.
struct EditorToolPanel {
  const ToolKind* kind;
  const char* header;
  void (*draw)(EditorCommands& c, FieldErrors& errs, Ui& ui);
};

const std::vector<EditorToolPanel>& editor_tool_panels() {
  static const std::vector<EditorToolPanel> panels = {
      {&FillingTool::kind(), "Bladder filling", filling_panel},
      {&ProbeTool::kind(), "Probe", probe_panel},
      {&NeedleTool::kind(), "Needle plan", needle_panel},
  };
  return panels;
}

}  // namespace

int run_editor(const EditorArgs& a) {
  int rc = 0;
  std::unique_ptr<EditorCommands> cmds;
  FieldErrors errs;
  auto open_doc = [&](const std::string& path, std::string& why) {
    try {
      cmds = std::make_unique<EditorCommands>(EditorCommands::open(path));
      errs.clear();
      return true;
    } catch (const std::exception& e) {
      why = e.what();
      return false;
    }
  };
  if (!a.scenario.empty()) {
    std::string why;
    if (!open_doc(a.scenario, why)) {
      std::fprintf(stderr, "error: %s\n", why.c_str());
      return 2;
    }
    if (const auto& e = cmds->doc().error()) std::fprintf(stderr, "warning: %s\n", issue_text(cmds->doc(), *e).c_str());
  }
  // scripted edits (through the same command path as the widgets)
  for (const std::string& kv : a.sets) {
    const size_t eq = kv.find('=');
    if (!cmds || eq == std::string::npos) {
      std::fprintf(stderr, "error: --set '%s': expected KEY=VALUE with a scenario\n", kv.c_str());
      return 2;
    }
    const std::string key = kv.substr(0, eq);
    const EditResult r = cmds->doc().set(key, kv.substr(eq + 1));
    errs.note(key, r);
    if (!r.ok) {
      std::fprintf(stderr, "error: %s\n", issue_text(cmds->doc(), *r.issue).c_str());
      rc = 2;
    }
  }
  if ((a.save || !a.save_as.empty()) && cmds && rc == 0) {
    try {
      cmds->save(a.save_as);
      std::printf("saved %s (model hash %016llx)\n", a.save_as.empty() ? cmds->doc().path().c_str() : a.save_as.c_str(),
                  static_cast<unsigned long long>(cmds->doc().model_hash()));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      rc = 2;
    }
  }

  const std::unique_ptr<window::AppWindow> win =
      window::AppWindow::open("ProstateSim scenario editor", 1600, 900, "error: cannot open a window (no display?)");
  if (!win) return 4;
  ImGuiIO& io = ImGui::GetIO();
  {
    Ui ui;
    Preview pv;
    std::snprintf(ui.open_path, sizeof ui.open_path, "%s", a.scenario.c_str());
    std::string shown_text;  // document text the preview was built from
    bool scripted_preview_done = false;
    int frame = 0;
    while (!win->should_close()) {
      win->poll_events();
      if (cmds && cmds->doc().text() != shown_text) {
        rebuild(pv, *cmds, ui);
        shown_text = cmds->doc().text();
      }
      if (a.preview_s > 0.0 && !scripted_preview_done && pv.runner) {
        // scripted preview: the same lock-step ticks as `prostatesim replay` / `run --unpaced`
        scripted_preview_done = true;
        pv.runner->advance_to(std::llround(a.preview_s / pv.scene->model->dt));
        std::printf("preview: %lld ticks, t = %.4g s, state hash %016llx%s\n", static_cast<long long>(pv.runner->tick()),
                    pv.scene->sim->state().time, static_cast<unsigned long long>(pv.runner->hash()), pv.runner->faulted() ? " (faulted)" : "");
      }
      // preview: the simulation runs in place, a few ticks a frame
      if (pv.running && pv.runner && !pv.runner->faulted()) {
        const int n = std::max(1, static_cast<int>(std::lround(0.016 / pv.scene->model->dt)));
        for (int k = 0; k < std::min(n, 8); ++k) pv.runner->step();
      }
      win->new_backend_frame();
      ImGui::NewFrame();
      const ImVec2 ds = io.DisplaySize;
      ImGui::SetNextWindowPos(ImVec2(0, 0));
      ImGui::SetNextWindowSize(ImVec2(kPanel, ds.y));
      ImGui::Begin("Scenario editor", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
      bool reopen = false;
      document_panel(cmds, errs, ui, reopen);
      if (cmds) {
        EditorCommands& c = *cmds;
        if (c.spec()) {
          if (ImGui::CollapsingHeader("Organs and materials", ImGuiTreeNodeFlags_DefaultOpen)) organ_panel(c, errs, ui);
          if (ImGui::CollapsingHeader("Lesions and targets", ImGuiTreeNodeFlags_DefaultOpen)) lesion_panel(c, errs, ui);
          for (const EditorToolPanel& p : editor_tool_panels())
            if (ImGui::CollapsingHeader(p.header, ImGuiTreeNodeFlags_DefaultOpen)) p.draw(c, errs, ui);
          if (ImGui::CollapsingHeader("Preview", ImGuiTreeNodeFlags_DefaultOpen)) {
            if (ImGui::Button(pv.running ? "Pause" : "Run")) pv.running = !pv.running;
            ImGui::SameLine();
            if (ImGui::Button("Reset")) { pv.running = false; if (pv.runner) pv.runner->reset(); }
            if (pv.runner) {
              ImGui::SameLine();
              ImGui::Text("t = %.3f s", pv.scene->sim->state().time);
              if (pv.runner->faulted()) ImGui::TextColored(kRed, "fault: %s", pv.scene->sim->state().fault.describe(*pv.scene->model).c_str());
            }
            if (!pv.error.empty()) ImGui::TextColored(kRed, "%s", pv.error.c_str());
          }
        }
        if (ImGui::CollapsingHeader("Any key", c.spec() ? 0 : ImGuiTreeNodeFlags_DefaultOpen)) any_key_panel(c, errs, ui);
      }
      ImGui::End();
      if (reopen) {
        std::string why;
        if (open_doc(ui.open_path, why)) { ui.status = std::string("opened ") + ui.open_path; ui.status_error = false; shown_text.clear(); pv = Preview{}; }
        else { ui.status = why; ui.status_error = true; }
      }

      // --- 3D view: handles drawn over it, picked and dragged in the view plane ---
      const float vx = kPanel, vw = std::max(1.0f, ds.x - kPanel), vh = std::max(1.0f, ds.y);
      render::Camera cam;
      if (pv.renderer) cam = render::preset_camera(render::View::Orbit, pv.renderer->scene(), nullptr, ui.orbit);
      std::vector<Handle> hs = cmds ? handles(*cmds) : std::vector<Handle>{};
      ImDrawList* fg = ImGui::GetForegroundDrawList();
      const bool in_view = !io.WantCaptureMouse && io.MousePos.x > vx;
      const ViewRect vr{vx, 0.0f, vw, vh};
      if (pv.renderer) {
        // the same ViewDrag calls as tests/editor/view_drag_test.cpp
        if (in_view && ImGui::IsMouseClicked(0)) ui.orbiting = !(cmds && ui.drag.press(*cmds, cam, vr, io.MousePos.x, io.MousePos.y));
        if (ImGui::IsMouseDown(0) && ui.drag.dragging()) {
          if (cmds) ui.drag.move(*cmds, cam, vr, io.MouseDelta.x, io.MouseDelta.y);
        } else if (ui.drag.dragging() && ImGui::IsMouseReleased(0)) {
          if (cmds) ui.drag.release(*cmds, errs);
        }
        if (!ImGui::IsMouseDown(0)) ui.orbiting = false;
        if (in_view) {
          const ImVec2 d = io.MouseDelta;
          if ((ui.orbiting && ImGui::IsMouseDown(0)) || ImGui::IsMouseDown(1)) ui.orbit.rotate(-0.3 * d.x, 0.3 * d.y);
          if (ImGui::IsMouseDown(2)) ui.orbit.pan(-d.x * ui.orbit.distance / vh, d.y * ui.orbit.distance / vh);
          if (io.MouseWheel != 0.0f) ui.orbit.zoom(std::pow(0.9, io.MouseWheel));
        }
        for (const Handle& h : hs) {
          const bool sel = h.name == ui.drag.selected() && h.kind == ui.drag.selected_kind();
          const Vec3 at = 1e-3 * (h.pos_mm + (sel && ui.drag.dragging() ? ui.drag.offset_mm() : Vec3::Zero()));
          ImVec2 p;
          float ppm = 0;
          if (!project(cam, vr, at, p.x, p.y, &ppm)) continue;
          const ImU32 col = sel ? IM_COL32(255, 230, 60, 255) : h.kind == Handle::Target ? IM_COL32(255, 80, 80, 255) : IM_COL32(80, 255, 120, 255);
          if (h.kind == Handle::Region) fg->AddCircle(p, std::max(6.0f, static_cast<float>(1e-3 * h.radius_mm) * ppm), col, 32, sel ? 3.0f : 1.5f);
          else {
            fg->AddLine(ImVec2(p.x - 8, p.y - 8), ImVec2(p.x + 8, p.y + 8), col, 2.0f);
            fg->AddLine(ImVec2(p.x - 8, p.y + 8), ImVec2(p.x + 8, p.y - 8), col, 2.0f);
          }
          char label[160];
          const Vec3 mm = 1e3 * at;
          std::snprintf(label, sizeof label, "%s [%.0f, %.0f, %.0f] mm", h.name.c_str(), mm.x(), mm.y(), mm.z());
          fg->AddText(ImVec2(p.x + 10, p.y - 18), col, label);
        }
        fg->AddText(ImVec2(vx + 10, vh - 22), IM_COL32(200, 200, 200, 255),
                    "left drag a lesion or target: move it in the view plane | left/right drag: orbit | wheel: zoom | Ctrl+Z / Ctrl+Y");
      } else {
        const char* why = !cmds ? "open a scenario file (left)" : pv.error.empty() ? "the scenario is invalid: fix it on the left" : pv.error.c_str();
        fg->AddText(ImVec2(vx + 20, vh * 0.5f), IM_COL32(230, 120, 120, 255), why);
      }

      ImGui::Render();
      int fbw = 0, fbh = 0;
      win->clear_framebuffer(fbw, fbh);
      const float sx = ds.x > 0 ? fbw / ds.x : 1.0f, sy = ds.y > 0 ? fbh / ds.y : 1.0f;
      if (pv.renderer && pv.runner) {
        try {
          const Snapshot& snap = pv.runner->snapshot();
          pv.renderer->update(snap);
          ui.ropt.viewport_x = static_cast<int>(vx * sx);
          ui.ropt.viewport_y = 0;
          ui.ropt.title = pv.scene->spec.name + (cmds && cmds->doc().modified() ? "  (modified)" : "");
          pv.renderer->render(cam, static_cast<int>(vw * sx), static_cast<int>(vh * sy), ui.ropt);
        } catch (const std::exception& e) {
          pv.error = e.what();
          pv.renderer.reset();
        }
      }
      win->draw_imgui();
      ++frame;
      const bool ending = win->should_close() || (a.frames >= 0 && frame >= a.frames);
      if (ending) {
        if (!a.screenshot.empty() && !window::write_framebuffer_png(a.screenshot, fbw, fbh)) rc = 2;
        win->close();
      }
      win->swap();
    }
  }
  return rc;
}

}  // namespace ps::editor
