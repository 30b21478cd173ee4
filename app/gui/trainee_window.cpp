#include "app/gui/trainee_window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes (ImGui 1.86 reads keys by GLFW code)
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "app/frames/us_isodose.h"
#include "app/gui/dose_worker.h"
#include "app/gui/metrics_panel.h"
#include "app/gui/plot_axes.h"
#include "app/gui/session.h"
#include "app/gui/tool_panels.h"
#include "app/gui/ultrasound_worker.h"
#include "app/window/app_window.h"
#include "engine/dosimetry/template_grid.h"
#include "engine/metrics/session_metrics.h"
#include "haptics/mouse_keyboard.h"
#include "engine/util/error.h"
#include "render/gl_api.h"
#include "render/render_error.h"
#include "render/renderer.h"

namespace ps::gui {

namespace {

constexpr float kLeftPanel = 330.0f, kRightPanel = 400.0f;  // panel widths [px]
constexpr double kPi = 3.14159265358979323846;
constexpr float kProbeDragDegPerPixel = 0.15f;  // Ctrl + drag: probe roll / tilt per pixel [deg]
constexpr float kProbeWheelMm = 2.0f;           // Ctrl + wheel: probe insertion per notch [mm]

struct Ui {
  render::View view = render::View::Orbit;
  render::OrbitCamera orbit;
  render::RenderOptions ropt;
  bool help = false;
  bool paused = false;
  ToolPanelState panels;          // the instruments' panels (probe pose, selected needle, ...)
  char open_path[512] = {};
  char state_path[512] = {};      // saved state to load (filled by "Save last good state")
  std::string error;              // last load error (file:line:field)
  std::deque<std::string> log;    // event log (newest last)
  std::vector<float> depth_mm, force_n;  // force-versus-depth of the active needle
  double frame_ms = 0.0;
  bool dragging_l = false, dragging_r = false;
  double mx = 0, my = 0;
};

// Test hook PROSTATESIM_CLICKS="Label one;Label two": clicks those buttons in turn, each as soon
// as it is shown, by feeding ImGui the mouse of a user (moved onto the button, pressed, released
// over it: three frames), so a test drives the very code of a click. Each click is printed.
struct ClickScript {
  std::vector<std::string> labels;
  size_t next = 0;
  int phase = 0;                  // 0 move onto it, 1 press, 2 release
  bool seen = false;              // the next button was drawn in the last frame
  ImVec2 at;
  explicit ClickScript(const char* spec) {
    for (std::string rest = spec ? spec : ""; !rest.empty();) {
      const size_t k = rest.find(';');
      if (k > 0) labels.push_back(rest.substr(0, k));
      rest = k == std::string::npos ? "" : rest.substr(k + 1);
    }
  }
  // after the platform backend's NewFrame, before ImGui::NewFrame (overrides the real pointer)
  void feed(ImGuiIO& io) {
    if (next >= labels.size() || !seen) return;
    io.MousePos = at;
    io.MouseDown[0] = phase == 1;
    if (phase == 2) {
      std::printf("click: %s\n", labels[next].c_str());
      std::fflush(stdout);
      ++next;
      seen = false;
      phase = 0;
    } else {
      ++phase;
    }
  }
  // ImGui::Button that notes where the scripted click must land
  bool button(const char* label) {
    const bool pressed = ImGui::Button(label);
    if (next < labels.size() && labels[next] == label && ImGui::IsItemVisible()) {
      const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
      at = ImVec2(0.5f * (a.x + b.x), 0.5f * (a.y + b.y));
      seen = true;
    }
    return pressed;
  }
  bool done() const { return next >= labels.size(); }
  // "hole C3": a click on the transverse image at that template hole (no button: the TRUS panel
  // says where it is shown, target())
  const std::string* wanted() const { return next < labels.size() ? &labels[next] : nullptr; }
  void target(ImVec2 p) {
    at = p;
    seen = true;
  }
};

// The live biplane TRUS images: a worker thread forms them from snapshots (ultrasound_worker.h),
// this uploads the newest ones into two textures and shows them side by side.
struct UsPanel {
  const Session* for_session = nullptr;
  std::unique_ptr<UltrasoundWorker> worker;
  std::string error;                 // why there is no image (no probe, anatomy failed)
  UsFrame frame;
  unsigned tex[2] = {0, 0};
  bool have = false;
  float gain_db = 0.0f, depth_mm = 60.0f, freq_mhz = 7.5f;  // the knobs (sliders)
  bool lesions = true, toggle_lesions = false;               // fused MRI contour of the lesions (M)
  bool zoom = true;                  // the transverse image zoomed on the template (a scene with one)
  // isodose lines of both planes (us_isodose.h), traced on this thread from the dose worker's
  // newest grid whenever it or the image changed
  std::vector<dosimetry::IsoSegment> iso[2];
  const dosimetry::DoseField* iso_field = nullptr;
  double iso_time = -1.0;
  ~UsPanel() {
    worker.reset();
    if (tex[0] && gl::loaded()) gl::api.DeleteTextures(2, tex);
  }
};

void us_panel(UsPanel& p, Session& s, const Snapshot& snap, float width, const dosimetry::DoseField* dose, NeedlePanelState& np,
              ClickScript& clicks) {
  if (p.for_session != &s) {  // a new scene: a new worker for its anatomy
    p.worker.reset();
    p.have = false;
    p.error.clear();
    p.for_session = &s;
    if (!s.has_probe()) p.error = "no TRUS probe in this scene";
    else {
      try {
        p.worker = std::make_unique<UltrasoundWorker>(s.scene());
        const UsControls c = p.worker->controls();
        p.gain_db = static_cast<float>(c.gain_db);
        p.depth_mm = static_cast<float>(c.depth_m * 1e3);
        p.freq_mhz = static_cast<float>(c.frequency_hz * 1e-6);
        p.lesions = c.lesions;
      } catch (const std::exception& e) {
        p.error = e.what();
      }
    }
  }
  if (p.worker) {
    p.worker->submit(snap);
    if (p.worker->take(p.frame)) {
      const int n = p.frame.side;
      if (!p.tex[0]) {
        gl::api.GenTextures(2, p.tex);
        for (unsigned t : p.tex) {
          gl::api.BindTexture(GL_TEXTURE_2D, t);
          gl::api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
          gl::api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
          gl::api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_G, GL_RED);  // gray from one channel
          gl::api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_B, GL_RED);
          gl::api.TexImage2D(GL_TEXTURE_2D, 0, GL_R8, n, n, 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
        }
      }
      gl::api.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
      const std::vector<uint8_t>* img[2] = {&p.frame.transverse, &p.frame.sagittal};
      for (int k = 0; k < 2; ++k) {
        gl::api.BindTexture(GL_TEXTURE_2D, p.tex[k]);
        gl::api.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, n, n, GL_RED, GL_UNSIGNED_BYTE, img[k]->data());
      }
      gl::api.BindTexture(GL_TEXTURE_2D, 0);
      p.have = true;
    }
  }
  const float side = 0.5f * (width - 8.0f);
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  if (!p.have) {
    ImGui::GetWindowDrawList()->AddRectFilled(p0, ImVec2(p0.x + width, p0.y + side), IM_COL32(8, 8, 8, 255));
    ImGui::GetWindowDrawList()->AddText(ImVec2(p0.x + 10, p0.y + 0.45f * side), IM_COL32(150, 150, 150, 255),
                                        p.error.empty() ? "forming the first ultrasound image..." : p.error.c_str());
    ImGui::Dummy(ImVec2(width, side));
    return;
  }
  if (dose != p.iso_field || p.frame.time != p.iso_time) {
    for (int k = 0; k < 2; ++k) {
      p.iso[k].clear();
      if (dose) frames::plane_isodose_lines(*dose, p.frame.plane[k], p.iso[k]);
    }
    p.iso_field = dose;
    p.iso_time = p.frame.time;
  }
  // the template (a brachytherapy scene): its holes where they cross the transverse plane; with
  // "zoom on template" the transverse image shows the part around the grid, as a brachytherapy
  // TRUS is set up, instead of the whole 140 degree sector
  np.grid.update(s, snap);
  const bool grid = np.grid.has_template();
  const frames::HoleMarks marks = grid ? frames::transverse_hole_marks(p.frame.plane[0], np.grid.holes) : frames::HoleMarks{};
  for (int k = 0; k < 2; ++k) {
    if (k) ImGui::SameLine(0.0f, 8.0f);
    const ImVec2 o = ImGui::GetCursorScreenPos();
    const frames::ImageCrop crop = k == 0 && grid && p.zoom ? frames::template_crop(marks, p.frame.side, o.x, o.y, side)
                                                            : frames::whole_image(p.frame.side, o.x, o.y, side);
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(p.tex[k])), ImVec2(side, side),
                 ImVec2(static_cast<float>(crop.u0()), static_cast<float>(crop.v0())), ImVec2(static_cast<float>(crop.u1()), static_cast<float>(crop.v1())));
    const bool hovered = ImGui::IsItemHovered();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(ImGui::GetItemRectMin(), ImGui::GetItemRectMax(), true);
    auto at = [&](float x, float y) {
      const frames::ImagePoint v = crop.to_view({x, y});
      return ImVec2(static_cast<float>(v.x), static_cast<float>(v.y));
    };
    for (const dosimetry::IsoSegment& g : p.iso[k]) {
      const auto& c = frames::kIsodoseRgb[std::min<size_t>(g.level, frames::kIsodoseRgb.size() - 1)];
      dl->AddLine(at(g.x0, g.y0), at(g.x1, g.y1), IM_COL32(c[0], c[1], c[2], 255), 1.5f);
    }
    if (grid && k == 0) {
      draw_transverse_template(dl, np.grid, marks, crop, np.hole_col, np.hole_row);
      if (const std::string* w = clicks.wanted(); w && w->rfind("hole ", 0) == 0)
        if (const auto cr = dosimetry::parse_template_hole(w->substr(5), np.grid.cols, np.grid.rows))
          for (size_t i = 0; i < marks.holes.size(); ++i)
            if (marks.holes[i].col == cr->first && marks.holes[i].row == cr->second) {
              const frames::ImagePoint v = crop.to_view(marks.at[i]);
              clicks.target(ImVec2(static_cast<float>(v.x), static_cast<float>(v.y)));
            }
      // a click picks the hole nearest to it (within half a spacing) as the panel's list does
      if (hovered) {
        const ImVec2 m = ImGui::GetIO().MousePos;
        const frames::ImagePoint px = crop.to_image(m.x, m.y);
        const int h = frames::pick_hole(marks, px.x, px.y);
        if (h >= 0) {
          const frames::TemplateHole& th = marks.holes[h];
          ImGui::SetTooltip("%s", dosimetry::template_hole_label(th.col, th.row).c_str());
          if (ImGui::IsMouseClicked(0) && s.needle_count() > 0) pick_template_hole(s, np, th.col, th.row);
        }
      }
    }
    if (grid && k == 1) draw_sagittal_plan(dl, np.grid, p.frame.plane[1], crop, np.hole_col, np.hole_row);
    dl->PopClipRect();
  }
  if (grid) {
    ImGui::TextDisabled("transverse (R on left; click a hole to aim)   sagittal (base on left)");
    ImGui::Checkbox("zoom on template", &p.zoom);
  } else {
    ImGui::TextDisabled("transverse (R on left)   sagittal (base on left)");
  }
  if (dose) ImGui::TextDisabled("isodose 50/100/150/200 %%: blue, red, yellow, magenta");
  ImGui::TextDisabled("t = %.3f s, both planes %.0f ms (worker thread)", p.frame.time, p.frame.ms);
  // gain, depth, frequency: the worker rebuilds its imager for them before its next image
  ImGui::PushItemWidth(0.3f * width);
  bool changed = ImGui::SliderFloat("gain [dB]", &p.gain_db, -30.0f, 30.0f, "%.0f");
  ImGui::SameLine();
  changed |= ImGui::SliderFloat("depth [mm]", &p.depth_mm, 30.0f, 100.0f, "%.0f");
  changed |= ImGui::SliderFloat("frequency [MHz]", &p.freq_mhz, 4.0f, 12.0f, "%.1f");
  ImGui::SameLine();
  changed |= ImGui::Checkbox("MRI contour (M)", &p.lesions);
  if (p.toggle_lesions) { p.lesions = !p.lesions; p.toggle_lesions = false; changed = true; }
  ImGui::PopItemWidth();
  if (changed && p.worker) {
    try {
      p.worker->set_controls({p.gain_db, p.depth_mm * 1e-3, p.freq_mhz * 1e6, p.lesions});
    } catch (const std::exception& e) {  // a typed-in value out of range (ctrl+click): say which
      p.error = e.what();
    }
  }
  if (!p.error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.4f, 1.0f), "%s", p.error.c_str());
}

// The live implant dosimetry (dose_worker.h): the indices and the cumulative DVH, updated by the
// worker thread as seeds drop and as the tissue carries them.
struct DosePanel {
  const Session* for_session = nullptr;
  std::unique_ptr<DoseWorker> worker;
  std::string error;
  DoseFrame frame;
  const dosimetry::IsoSurface* shown = nullptr;  // the surface last given to the 3D view's renderer
  // the newest dose grid once a seed is in (the TRUS panel's isodose lines), else null
  const dosimetry::DoseField* field() const { return frame.ready && frame.seeds > 0 ? frame.field.get() : nullptr; }
};

void dose_panel(DosePanel& p, Session& s, const Snapshot& snap, float width) {
  if (p.for_session != &s) {
    p.worker.reset();
    p.frame = DoseFrame{};
    p.shown = nullptr;
    p.error.clear();
    p.for_session = &s;
    if (!frames::SnapshotDose::scene_has_seeds(s.scene())) p.error = "no seeds planned in this scene";
    else {
      try {
        p.worker = std::make_unique<DoseWorker>(s.scene());
      } catch (const std::exception& e) {
        p.error = e.what();
      }
    }
  }
  if (!p.error.empty()) {
    ImGui::TextDisabled("%s", p.error.c_str());
    return;
  }
  p.worker->submit(snap);
  p.worker->take(p.frame);
  if (!p.frame.ready) {
    ImGui::TextDisabled("computing the first dose grid...");
    return;
  }
  const auto& x = p.frame.indices;
  const double rx = p.worker->prescription_gy();
  ImGui::Text("%d seeds, I-125 6711, prescription %.0f Gy", p.frame.seeds, rx);
  ImGui::Text("prostate D90 %.0f Gy (%.0f %%)  V100 %.1f %%  V150 %.1f %%  V200 %.1f %%", x.prostate_d90_gy,
              100.0 * x.prostate_d90_gy / rx, 100 * x.prostate_v100, 100 * x.prostate_v150, 100 * x.prostate_v200);
  ImGui::Text("urethra D10 %.0f Gy  D30 %.0f Gy   rectum D2cc %.0f Gy  V100 %.2f cc", x.urethra_d10_gy, x.urethra_d30_gy,
              x.rectum_d2cc_gy, x.rectum_v100_cc);
  // cumulative DVH: volume [%] against dose [% of prescription], 0..250 %
  const float h = 150.0f, w = width - 20.0f;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, ImVec2(p0.x + w, p0.y + h), IM_COL32(250, 250, 250, 255));
  auto X = [&](double pct) { return p0.x + static_cast<float>(pct / 250.0) * w; };
  auto Y = [&](double frac) { return p0.y + h - static_cast<float>(frac) * h; };
  for (int pct : {50, 100, 150, 200}) {
    dl->AddLine(ImVec2(X(pct), p0.y), ImVec2(X(pct), p0.y + h), IM_COL32(200, 200, 200, 255));
    dl->AddText(ImVec2(X(pct) + 2, p0.y + h - 14), IM_COL32(120, 120, 120, 255), (std::to_string(pct) + "%").c_str());
  }
  const auto& c = p.frame.dvh;
  const std::vector<double>* ys[3] = {&c.prostate, &c.urethra, &c.rectum};
  const ImU32 col[3] = {IM_COL32(200, 40, 40, 255), IM_COL32(230, 160, 0, 255), IM_COL32(60, 90, 200, 255)};
  for (int k = 0; k < 3; ++k)
    for (size_t i = 1; i < c.dose_gy.size(); ++i)
      dl->AddLine(ImVec2(X(100.0 * c.dose_gy[i - 1] / rx), Y((*ys[k])[i - 1])), ImVec2(X(100.0 * c.dose_gy[i] / rx), Y((*ys[k])[i])),
                  col[k], 2.0f);
  ImGui::Dummy(ImVec2(w, h));
  ImGui::TextDisabled("DVH: prostate (red), urethra (orange), rectum (blue); t = %.2f s, %.1f ms + isodose %.1f ms (worker thread)",
                      p.frame.time, p.frame.ms, p.frame.iso_ms);
}

void push_log(Ui& ui, const std::string& s) {
  ui.log.push_back(s);
  while (ui.log.size() > 400) ui.log.pop_front();
}

void reset_view(Ui& ui, Session& s) {
  ui.orbit = render::OrbitCamera{};
  ui.orbit.target = s.renderer().scene().focus;
  ui.orbit.distance = s.renderer().scene().extent * 3.2;
  ui.ropt.opacity.clear();
  for (const auto& surf : s.renderer().scene().surfaces) ui.ropt.opacity.push_back(surf.colour.a);
  ui.ropt.hidden.assign(s.renderer().scene().surfaces.size(), 0);
  ui.panels.probe.reset(s.initial_probe_pose());
  ui.depth_mm.clear();
  ui.force_n.clear();
  ui.panels.needle.needle = 0;
  ui.panels.needle.hole_col = ui.panels.needle.hole_row = -1;
}

// force versus depth, drawn with ImDrawList (ImPlot is not packaged)
void force_plot(const Ui& ui, ImVec2 size) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  dl->AddRectFilled(p0, p1, IM_COL32(20, 22, 26, 255));
  const float ml = 34, mb = 18;
  // axes: depth 0..dmax on steps of a quarter (10, 20, 40, ... mm), force from fmin (0, or below
  // when the needle is pulled back: the shaft's friction points the other way) to fmax [N]
  float dmax = 10.0f, fmax = 1.0f, fmin = 0.0f;
  for (float d : ui.depth_mm) dmax = std::max(dmax, d);
  for (float f : ui.force_n) {
    fmax = std::max(fmax, f);
    fmin = std::min(fmin, f);
  }
  dmax = depth_axis_max(dmax);
  const ForceAxis fa = force_axis(fmin, fmax);  // four round steps: 0 is a grid line when in range
  fmin = fa.lo;
  fmax = fa.hi();
  auto X = [&](float d) { return p0.x + ml + (size.x - ml - 6) * d / dmax; };
  auto Y = [&](float f) { return p1.y - mb - (size.y - mb - 6) * (f - fmin) / (fmax - fmin); };
  for (int k = 0; k <= 4; ++k) {
    const float d = dmax * k / 4, f = fmin + (fmax - fmin) * k / 4;
    dl->AddLine(ImVec2(X(d), p0.y + 4), ImVec2(X(d), p1.y - mb), IM_COL32(60, 62, 70, 255));
    dl->AddLine(ImVec2(p0.x + ml, Y(f)), ImVec2(p1.x - 4, Y(f)), IM_COL32(60, 62, 70, 255));
    char b[16];
    std::snprintf(b, sizeof b, "%.3g", d);
    dl->AddText(ImVec2(X(d) - 6, p1.y - mb + 2), IM_COL32(200, 200, 200, 255), b);
    std::snprintf(b, sizeof b, "%.3g", f);
    dl->AddText(ImVec2(p0.x + 4, Y(f) - 7), IM_COL32(200, 200, 200, 255), b);
  }
  if (fmin < 0) dl->AddLine(ImVec2(p0.x + ml, Y(0)), ImVec2(p1.x - 4, Y(0)), IM_COL32(120, 122, 130, 255));
  dl->PushClipRect(ImVec2(p0.x + ml, p0.y), ImVec2(p1.x, p1.y - mb), true);  // the curve stays in the plot
  for (size_t k = 1; k < ui.depth_mm.size(); ++k)
    dl->AddLine(ImVec2(X(ui.depth_mm[k - 1]), Y(ui.force_n[k - 1])), ImVec2(X(ui.depth_mm[k]), Y(ui.force_n[k])),
                IM_COL32(255, 150, 40, 255), 2.0f);
  dl->PopClipRect();
  dl->AddText(ImVec2(p0.x + ml + 4, p0.y + 4), IM_COL32(230, 230, 230, 255), "force [N] vs depth [mm]");
  ImGui::Dummy(size);
}

void help_overlay(Ui& ui) {
  ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowBgAlpha(0.92f);
  ImGui::Begin("Help: mouse and keyboard", &ui.help, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
  const char* rows[][2] = {
      {"left drag (vertical)", "needle depth (mouse+keyboard device), else orbit"},
      {"Ctrl + left drag", "probe: across turns it about its axis, up/down angles it about the anal pivot"},
      {"Ctrl + wheel, PgUp / PgDn", "probe: push in / pull out"},
      {"[ / ]", "probe: turn left / right (2 deg)"},
      {"--probe-device spacemouse", "probe in 6 DOF from a SpaceMouse (run option)"},
      {"right drag", "orbit the 3D view"}, {"middle drag", "pan"}, {"wheel", "zoom"},
      {"1 2 3 4 5", "views: 3D, anterior, lateral, along probe, side-on to needle"},
      {"W / S (hold)", "advance / retract the active needle"}, {"Q / E", "turn the needle hub"},
      {"Tab", "next needle"}, {"Space", "fire the biopsy gun"}, {"D", "deposit a seed"},
      {"Shift (hold)", "clutch: move the hand without the needle"},
      {"P", "pause / resume"}, {"R", "restart the scenario"}, {"C", "displacement colours"},
      {"A", "force arrows"}, {"M", "lesions' fused MRI contour on the ultrasound"}, {"H or F1", "this help"}, {"Esc", "close the help"}};
  if (ImGui::BeginTable("bindings", 2, ImGuiTableFlags_RowBg)) {
    for (auto& r : rows) {
      ImGui::TableNextRow();
      ImGui::TableSetColumnIndex(0);
      ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.4f, 1.0f), "%s", r[0]);
      ImGui::TableSetColumnIndex(1);
      ImGui::TextUnformatted(r[1]);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

// The newest snapshot: its events into the log, the active needle's force and depth into the plot.
void read_snapshot(Ui& ui, Session& s, const Snapshot& snap) {
  for (const SnapshotEvent& e : s.new_events()) {
    char b[200];
    std::snprintf(b, sizeof b, "%7.3f s  %s", e.time, e.text.data());
    push_log(ui, b);
  }
  const ToolReadout* active = nullptr;
  for (const auto& t : snap.tools)
    if ((t.carries & kCarriesInsertion) && (t.active || !active)) active = &t;
  if (active && active->depth > 0.0 && (ui.depth_mm.empty() || std::abs(ui.depth_mm.back() - active->depth * 1e3) > 0.01)) {
    ui.depth_mm.push_back(static_cast<float>(active->depth * 1e3));
    ui.force_n.push_back(static_cast<float>(active->force));
    if (ui.depth_mm.size() > 20000) {
      ui.depth_mm.erase(ui.depth_mm.begin(), ui.depth_mm.begin() + 10000);
      ui.force_n.erase(ui.force_n.begin(), ui.force_n.begin() + 10000);
    }
  }
}

// Keys when ImGui does not want them: views, pause, restart, overlays, the probe, and the needle
// (to the run's mouse+keyboard device when it has one, docs/realtime.md, else as commands).
void handle_keys(Ui& ui, Session& s, UsPanel& us, bool& up_held, bool& down_held) {
  auto pressed = [&](int key) { return ImGui::IsKeyPressed(key, false); };
  if (pressed(GLFW_KEY_1)) ui.view = render::View::Orbit;
  if (pressed(GLFW_KEY_2)) ui.view = render::View::Anterior;
  if (pressed(GLFW_KEY_3)) ui.view = render::View::Lateral;
  if (pressed(GLFW_KEY_4)) ui.view = render::View::Probe;
  if (pressed(GLFW_KEY_5)) ui.view = render::View::Needle;
  if (pressed(GLFW_KEY_P)) { ui.paused = !ui.paused; s.pause(ui.paused); }
  if (pressed(GLFW_KEY_R)) { s.restart(); reset_view(ui, s); push_log(ui, "restarted"); }
  if (pressed(GLFW_KEY_C)) ui.ropt.displacement = !ui.ropt.displacement;
  if (pressed(GLFW_KEY_A)) ui.ropt.force_arrows = !ui.ropt.force_arrows;
  if (pressed(GLFW_KEY_H) || pressed(GLFW_KEY_F1)) ui.help = !ui.help;
  if (pressed(GLFW_KEY_ESCAPE)) ui.help = false;
  if (pressed(GLFW_KEY_M)) us.toggle_lesions = true;
  if (s.has_probe()) {
    bool moved = false;
    auto step = [&](int key, float& v, float by, float lo, float hi) {
      if (ImGui::IsKeyPressed(key, true)) { v = std::clamp(v + by, lo, hi); moved = true; }
    };
    step(GLFW_KEY_PAGE_UP, ui.panels.probe.insertion_mm, 1.0f, 0.0f, 80.0f);
    step(GLFW_KEY_PAGE_DOWN, ui.panels.probe.insertion_mm, -1.0f, 0.0f, 80.0f);
    step(GLFW_KEY_LEFT_BRACKET, ui.panels.probe.roll_deg, -2.0f, -90.0f, 90.0f);
    step(GLFW_KEY_RIGHT_BRACKET, ui.panels.probe.roll_deg, 2.0f, -90.0f, 90.0f);
    if (moved) ui.panels.probe.command(s);
  }
  if (haptics::MouseKeyboardDevice* m = s.mouse()) {
    using K = haptics::MouseKeyboardDevice;
    const std::pair<int, K::Key> keys[] = {{GLFW_KEY_W, K::W}, {GLFW_KEY_S, K::S}, {GLFW_KEY_Q, K::Q}, {GLFW_KEY_E, K::E},
                                           {GLFW_KEY_SPACE, K::Space}, {GLFW_KEY_D, K::D}, {GLFW_KEY_TAB, K::Tab},
                                           {GLFW_KEY_LEFT_SHIFT, K::Shift}, {GLFW_KEY_UP, K::Up}, {GLFW_KEY_DOWN, K::Down},
                                           {GLFW_KEY_LEFT, K::Left}, {GLFW_KEY_RIGHT, K::Right}};
    for (auto [g, k] : keys) {
      if (ImGui::IsKeyPressed(g, false)) m->key(k, true);
      if (ImGui::IsKeyReleased(g)) m->key(k, false);
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_TAB, false) && s.needle_count() > 0) ui.panels.needle.needle = (ui.panels.needle.needle + 1) % s.needle_count();
  } else {
    if (pressed(GLFW_KEY_SPACE)) s.fire(ui.panels.needle.needle);
    if (pressed(GLFW_KEY_D)) s.seed(ui.panels.needle.needle);
    if (pressed(GLFW_KEY_TAB) && s.needle_count() > 0) { ui.panels.needle.needle = (ui.panels.needle.needle + 1) % s.needle_count(); s.select(ui.panels.needle.needle); }
    const bool up = ImGui::IsKeyDown(GLFW_KEY_W), down = ImGui::IsKeyDown(GLFW_KEY_S);
    if (up != up_held || down != down_held)
      s.advance(ui.panels.needle.needle, up ? ui.panels.needle.speed_mm_s * 1e-3 : down ? -ui.panels.needle.speed_mm_s * 1e-3 : 0.0);
    up_held = up;
    down_held = down;
  }
}

// A scenario to switch to after this frame (Open, Record): the running session stays valid until then.
struct PendingSwitch {
  bool pending = false;
  std::string path, record, log;
};

// The left panel: the scenario, pause / restart / record, saved states, each instrument's panel,
// the view and rendering options.
void instruments_panel(Ui& ui, Session& s, const Snapshot& snap, ClickScript& clicks, PendingSwitch& next, ImVec2 ds) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(kLeftPanel, ds.y));
  ImGui::Begin("Instruments", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::TextColored(ImVec4(0.6f, 0.9f, 1.0f, 1.0f), "%s", s.name().c_str());
  ImGui::InputText("##open", ui.open_path, sizeof ui.open_path);
  ImGui::SameLine();
  if (ImGui::Button("Open")) {
    next.pending = true;  // switched after this frame: `s` stays valid until then
    next.path = ui.open_path;
    next.record.clear();
    next.log = std::string("loaded ") + ui.open_path;
  }
  if (!ui.error.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", ui.error.c_str());
  if (ImGui::Button(ui.paused ? "Resume" : "Pause")) { ui.paused = !ui.paused; s.pause(ui.paused); }
  ImGui::SameLine();
  if (ImGui::Button("Restart")) { s.restart(); reset_view(ui, s); push_log(ui, "restarted"); }
  ImGui::SameLine();
  if (ImGui::Button(s.recording() ? "Stop recording" : "Record")) {
    next.pending = true;
    next.path = s.file();
    if (s.recording()) {
      next.record.clear();
      next.log = "recording saved: " + s.recording_path() + " (scene restarted)";
    } else {
      std::filesystem::create_directories("out/recordings");
      next.record = "out/recordings/" + s.name() + ".rec";
      next.log = "recording to " + next.record + " from a fresh start";
    }
  }
  // a saved state of this scenario (`run --save-on-fault`, "Save last good state" below)
  ImGui::InputTextWithHint("##state", "saved state file (.state)", ui.state_path, sizeof ui.state_path);
  ImGui::SameLine();
  if (clicks.button("Load state")) {
    try {
      const SavedState st = s.load_state(ui.state_path);
      ui.error.clear();
      push_log(ui, "loaded state " + std::string(ui.state_path) + " (tick " + std::to_string(st.tick) + ")");
      std::printf("loaded state %s: tick %lld, state hash %s\n", ui.state_path, static_cast<long long>(st.tick),
                  hex16(st.state_hash).c_str());
    } catch (const std::exception& e) {
      ui.error = e.what();  // nothing changed: the scene runs on
      push_log(ui, std::string("load state failed: ") + e.what());
      std::fprintf(stderr, "error: %s\n", e.what());
    }
  }
  ImGui::Separator();
  draw_tool_controls(s, snap, ui.panels);  // each instrument kind's panel (tool_panels.h)
  ImGui::Text("View");
  const char* views[] = {"3D", "anterior", "lateral", "probe", "needle"};
  int v = static_cast<int>(ui.view == render::View::Orbit ? 0 : static_cast<int>(ui.view) + 1);
  if (ImGui::Combo("camera", &v, views, 5))
    ui.view = v == 0 ? render::View::Orbit : static_cast<render::View>(v - 1);
  ImGui::Checkbox("displacement [mm]", &ui.ropt.displacement);
  if (ui.ropt.displacement) {
    float m = static_cast<float>(ui.ropt.displacement_max_mm);
    if (ImGui::SliderFloat("scale max [mm]", &m, 0.5f, 20.0f)) ui.ropt.displacement_max_mm = m;
  }
  ImGui::Checkbox("force arrows", &ui.ropt.force_arrows);
  ImGui::Text("opacity");
  const auto& surfaces = s.renderer().scene().surfaces;
  for (size_t i = 0; i < surfaces.size() && i < ui.ropt.opacity.size(); ++i)
    ImGui::SliderFloat(surfaces[i].name.c_str(), &ui.ropt.opacity[i], 0.0f, 1.0f);
  if (ImGui::Button("Help (H)")) ui.help = true;
  ImGui::End();
}

// The right panel: force versus depth, the TRUS planes, metrics, dosimetry, instrument read-outs,
// timing and the event log.
void readouts_panel(Ui& ui, Session& s, const Snapshot& snap, UsPanel& us, DosePanel& dose, ClickScript& clicks, ImVec2 ds) {
  ImGui::SetNextWindowPos(ImVec2(ds.x - kRightPanel, 0));
  ImGui::SetNextWindowSize(ImVec2(kRightPanel, ds.y));
  ImGui::Begin("Read-outs", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  if (ImGui::CollapsingHeader("Force versus depth", ImGuiTreeNodeFlags_DefaultOpen)) {
    const bool needles = std::any_of(snap.tools.begin(), snap.tools.end(), [](const ToolReadout& r) { return (r.carries & kCarriesInsertion) != 0; });
    if (needles) force_plot(ui, ImVec2(kRightPanel - 20, 190));
    else ImGui::TextDisabled("no needle in this scene");
  }
  if (ImGui::CollapsingHeader("Ultrasound", ImGuiTreeNodeFlags_DefaultOpen)) us_panel(us, s, snap, kRightPanel - 20, dose.field(), ui.panels.needle, clicks);
  if (ImGui::CollapsingHeader("Metrics", ImGuiTreeNodeFlags_DefaultOpen)) metrics_panel(s, snap);
  if (ImGui::CollapsingHeader("Dosimetry", ImGuiTreeNodeFlags_DefaultOpen)) dose_panel(dose, s, snap, kRightPanel - 20);
  draw_tool_readouts(s, snap, ui.panels);
  if (ImGui::CollapsingHeader("Timing", ImGuiTreeNodeFlags_DefaultOpen)) {
    const LoopTiming t = s.timing();
    ImGui::Text("sim time %.3f s   tick %lld", snap.time, static_cast<long long>(snap.tick));
    // LoopTiming::slow_motion: the loop fell more than two ticks behind in the window; it is slow
    // motion to the trainee only when the window's factor fell short too (else it caught up)
    const bool slow = t.slow_motion && t.realtime_factor < 0.98 * t.target_factor;
    ImGui::Text("tick rate %.0f Hz   real-time factor %.2f%s", t.achieved_hz, t.realtime_factor,
                slow ? " (slow motion)" : t.slow_motion ? " (caught up)" : "");
    ImGui::Text("tick compute p50 %.2f, p99 %.2f ms (run p99 %.2f)", t.tick_p50_ms, t.tick_p99_ms, t.run_tick_p99_ms);
    ImGui::Text("frame %.1f ms (%.0f fps)", ui.frame_ms, ui.frame_ms > 0 ? 1000.0 / ui.frame_ms : 0.0);
  }
  if (ImGui::CollapsingHeader("Events", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::BeginChild("log", ImVec2(0, 0), true);
    for (const auto& l : ui.log) ImGui::TextWrapped("%s", l.c_str());  // the depth and force at the end stay in view
    if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
    ImGui::EndChild();
  }
  ImGui::End();
}

// Recovery when the physics stopped, over the 3D view where the trainee looks: save the last good
// state (loadable with "Load state" or `run --state`), restart.
void fault_overlay(Ui& ui, Session& s, const Snapshot& snap, ClickScript& clicks, ImVec2 ds) {
  // recovery (issue 14): the physics stopped; shown over the 3D view, where the trainee
  // looks: save the last good state (loadable with "Load state" or `run --state`), restart
  ImGui::SetNextWindowPos(ImVec2(kLeftPanel + 20, 40));
  ImGui::SetNextWindowSize(ImVec2(std::max(300.0f, ds.x - kLeftPanel - kRightPanel - 40), 0));
  ImGui::SetNextWindowBgAlpha(0.92f);
  ImGui::Begin("Simulation fault", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "The physics stopped: %s", snap.fault.data());
  ImGui::PopTextWrapPos();
  SavedState st;
  if (clicks.button("Save last good state")) {
    if (!s.loop().last_good_state(st)) {
      push_log(ui, "no last good state kept");
    } else {
      const std::string path = s.name() + "-tick" + std::to_string(st.tick) + ".state";
      try {
        app::save_fault_state(path, st, s.scene());
        push_log(ui, "last good state saved to " + path);
        std::snprintf(ui.state_path, sizeof ui.state_path, "%s", path.c_str());
      } catch (const std::exception& e) {
        push_log(ui, std::string("save failed: ") + e.what());
        std::fprintf(stderr, "error: %s\n", e.what());
      }
    }
  }
  ImGui::SameLine();
  if (clicks.button("Restart scene")) {
    s.restart();
    reset_view(ui, s);
    push_log(ui, "restarted after a fault");
    std::printf("restarted after a fault\n");
  }
  ImGui::End();
}

// The mouse over the 3D view: Ctrl holds the probe as its handle (drag across turns it about its
// axis, drag up / down angles it about the anal pivot, the wheel pushes and pulls it); otherwise
// the needle's depth (device), orbit, pan and zoom.
void handle_view_mouse(Ui& ui, Session& s, const ImGuiIO& io, float vh) {
  const ImVec2 d = io.MouseDelta;
  // Ctrl: the probe as its handle is held: drag across turns it about its axis (roll),
  // drag up / down angles it about the anal pivot (tilt), the wheel pushes and pulls it
  const bool hold_probe = io.KeyCtrl && s.has_probe();
  if (hold_probe) {
    bool moved = false;
    if (ImGui::IsMouseDown(0) && (d.x != 0.0f || d.y != 0.0f)) {
      ui.panels.probe.roll_deg = std::clamp(ui.panels.probe.roll_deg + kProbeDragDegPerPixel * d.x, -90.0f, 90.0f);
      ui.panels.probe.tilt_deg = std::clamp(ui.panels.probe.tilt_deg - kProbeDragDegPerPixel * d.y, -20.0f, 20.0f);
      moved = true;
    }
    if (io.MouseWheel != 0.0f) {
      ui.panels.probe.insertion_mm = std::clamp(ui.panels.probe.insertion_mm + kProbeWheelMm * io.MouseWheel, 0.0f, 80.0f);
      moved = true;
    }
    if (moved) ui.panels.probe.command(s);
  } else {
    if (ImGui::IsMouseDown(0) && s.mouse()) s.mouse()->drag(d.y);  // needle depth (device)
    else if (ImGui::IsMouseDown(0) || ImGui::IsMouseDown(1)) { ui.view = render::View::Orbit; ui.orbit.rotate(-0.3 * d.x, 0.3 * d.y); }
    if (ImGui::IsMouseDown(2)) { ui.view = render::View::Orbit; ui.orbit.pan(-d.x * ui.orbit.distance / vh, d.y * ui.orbit.distance / vh); }
    if (io.MouseWheel != 0.0f) ui.orbit.zoom(std::pow(0.9, io.MouseWheel));
  }
}

}  // namespace

int run_window(app::RunSession& run) {
  const char* shot_env = std::getenv("PROSTATESIM_SCREENSHOT");
  const std::string screenshot = shot_env ? shot_env : "";
  const std::unique_ptr<window::AppWindow> win = window::AppWindow::open(
      "ProstateSim trainee", 1600, 900,
      "error: cannot open a window (no display?); use `prostatesim replay ... --out DIR` for headless frames");
  if (!win) return 4;
  int rc = 0;
  {
    ImGuiIO& io = ImGui::GetIO();

    Ui ui;
    ClickScript clicks(std::getenv("PROSTATESIM_CLICKS"));
    UsPanel us;  // destroyed at the end of this block, while the GL context is still current
    DosePanel dose;
    ui.help = std::getenv("PROSTATESIM_HELP") != nullptr;
    const double factor = run.loop.factor();
    std::unique_ptr<Session> session = std::make_unique<Session>(run);
    reset_view(ui, *session);
    std::snprintf(ui.open_path, sizeof ui.open_path, "%s", run.scenario_path.c_str());
    push_log(ui, "loaded " + run.scenario_path);
    // replaces the running session (the run command's own loop is paused, not stopped)
    auto switch_to = [&](const std::string& path, const std::string& record_to) {
      try {
        auto opened = std::make_unique<Session>(path, factor, record_to);
        session->pause(true);
        session = std::move(opened);
        reset_view(ui, *session);
        ui.paused = false;
        ui.error.clear();
        return true;
      } catch (const std::exception& e) {
        ui.error = e.what();  // the last good scene keeps running
        push_log(ui, std::string("load failed: ") + e.what());
        return false;
      }
    };
    int frame = 0, us_wait = 0, click_wait = 0;
    PendingSwitch next;
    auto last = std::chrono::steady_clock::now();
    bool up_held = false, down_held = false;
    while (!win->should_close()) {
      win->poll_events();
      win->new_backend_frame();
      clicks.feed(io);
      ImGui::NewFrame();
      Session& s = *session;

      const Snapshot& snap = s.latest();
      read_snapshot(ui, s, snap);

      if (!io.WantCaptureKeyboard) handle_keys(ui, s, us, up_held, down_held);

      const ImVec2 ds = io.DisplaySize;
      instruments_panel(ui, s, snap, clicks, next, ds);
      readouts_panel(ui, s, snap, us, dose, clicks, ds);
      if (ui.help) help_overlay(ui);
      if (snap.faulted) fault_overlay(ui, s, snap, clicks, ds);

      // the 3D view between the panels
      const float vx = kLeftPanel, vw = std::max(1.0f, ds.x - kLeftPanel - kRightPanel), vh = ds.y;
      if (!io.WantCaptureMouse) handle_view_mouse(ui, s, io, vh);
      const render::Camera cam = render::preset_camera(ui.view, s.renderer().scene(), &snap, ui.orbit);
      // the template's labels and the plan's needles over the 3D view (under the panels)
      draw_template_3d(ImGui::GetBackgroundDrawList(), ui.panels.needle.grid, cam.projection(vw / vh) * cam.view(), vx, 0.0f, vw, vh,
                       ui.panels.needle.hole_col, ui.panels.needle.hole_row);
      ImGui::Render();
      int fbw = 0, fbh = 0;
      win->clear_framebuffer(fbw, fbh);
      const float sx = ds.x > 0 ? fbw / ds.x : 1.0f, sy = ds.y > 0 ? fbh / ds.y : 1.0f;
      s.renderer().update(snap);
      if (dose.for_session == &s && dose.frame.surface.get() != dose.shown) {  // a newer prescription isodose
        dose.shown = dose.frame.surface.get();
        s.renderer().set_isodose(dose.shown ? *dose.shown : dosimetry::IsoSurface{});
      }
      ui.ropt.viewport_x = static_cast<int>(vx * sx);
      ui.ropt.viewport_y = 0;
      ui.ropt.title = s.name() + "  [" + render::view_name(ui.view) + "]" + (ui.paused ? "  PAUSED" : "");
      s.renderer().render(cam, static_cast<int>(vw * sx), static_cast<int>(vh * sy), ui.ropt);
      win->draw_imgui();
      ++frame;
      bool ending = win->should_close() || (s.end_tick() >= 0 && snap.tick >= s.end_tick());
      // scripted clicks (PROSTATESIM_CLICKS) are made before the end (up to ~10 s more: a click on
      // the TRUS image waits for its first image)
      if (ending && !clicks.done() && !win->should_close() && click_wait < 1000) {
        ending = false;
        ++click_wait;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      // a screenshot waits (up to ~5 s) for the first ultrasound image from the worker thread
      if (ending && !screenshot.empty() && !win->should_close() && us.worker && !us.have && us_wait < 500) {
        ending = false;
        ++us_wait;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      if (ending) {
        if (!screenshot.empty() && !window::write_framebuffer_png(screenshot, fbw, fbh)) rc = 2;
        win->close();
      }
      win->swap();
      const auto now = std::chrono::steady_clock::now();
      ui.frame_ms = 0.9 * ui.frame_ms + 0.1 * std::chrono::duration<double, std::milli>(now - last).count();
      last = now;
      if (next.pending) {
        next.pending = false;
        if (switch_to(next.path, next.record)) push_log(ui, next.log);
      }
    }
    session.reset();  // stops the physics thread, finishes a recording
  }
  return rc;
}

}  // namespace ps::gui
