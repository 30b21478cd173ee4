#include "app/frames/frame_recorder.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include "app/frames/contact_sheet.h"
#include "engine/io/png_write.h"
#include "app/frames/png_queue.h"
#include "app/frames/us_isodose.h"
#include "engine/model/model.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/ultrasound/imager.h"
#include "engine/util/error.h"
#include "engine/util/atomic_file.h"
#include "render/headless_context.h"
#include "render/offscreen_target.h"
#include "render/renderer.h"

namespace ps::frames {

namespace fs = std::filesystem;

namespace {
FrameOptions checked(FrameOptions o, const UltrasoundInput* us) {
  if (!o.us_views.empty()) {
    if (!us) throw InputError("", 0, "--views", "ultrasound views need a scenario with a probe: section");
    us::UltrasoundSettings set = us->settings;
    set.width = set.height = o.us_size;
    us::validate(set, "--views");
  }
  return o;
}
}  // namespace

struct FrameRecorder::Impl {
  FrameOptions opt;
  std::unique_ptr<us::UltrasoundAnatomy> us_anatomy;       // the imagers keep a reference
  std::vector<std::unique_ptr<us::PlaneImager>> imagers;   // one per opt.us_views
  us::UltrasoundScene us_scene;
  us::ProbeView probe_view;                                // last seen in a snapshot
  int template_cols = 0, template_rows = 0;                // the probe's template (0: none)
  std::vector<PlannedHole> plan;                           // the scene's planned holes
  std::unique_ptr<SnapshotDose> dose;                      // a scene with seeds: isodose views
  std::vector<dosimetry::IsoSegment> iso_segments;
  render::HeadlessContext ctx;     // first: no GL, nothing written
  bool folder_ready;               // then the folder (refused when not empty or not writable)
  render::Antialias aa;            // opt.antialias resolved for this GL
  render::Renderer renderer;
  render::OffscreenTarget target;
  render::OrbitCamera orbit;
  PngQueue queue;
  int frame = 0;
  std::vector<double> render_ms;
  std::vector<double> us_ms;                               // one ultrasound plane [ms]
  std::string events;
  std::vector<std::string> tool_names;
  std::vector<double> t, depth, force;                     // active needle samples
  std::vector<double> fill_t, fill_ml, probe_t, probe_n;   // first filling's target volume, first probe's contact force
  std::vector<std::pair<double, double>> marks;            // (depth mm, force N) at punctures
  std::vector<std::string> mark_labels;
  std::vector<Thumb> thumbs;                               // contact sheet frames
  std::vector<int> thumb_frames;

  Impl(const Model& m, FrameOptions o, const UltrasoundInput* us, std::unique_ptr<SnapshotDose> d)
      : opt(checked(std::move(o), us)),
        dose(std::move(d)),
        folder_ready((prepare_output_dir(opt.out_dir, opt.force), true)),
        aa(render::resolve_antialias(opt.antialias, ctx.renderer())),
        renderer(render::make_render_scene(m, opt.shapes)),
        target(opt.width, opt.height, aa == render::Antialias::Msaa ? 4 : 0),
        queue(6) {
    orbit.target = renderer.scene().focus;
    orbit.distance = renderer.scene().extent * 3.2;
    const int n = std::max(1, opt.expected_frames);
    for (int k = 0; k < 4; ++k) thumb_frames.push_back(static_cast<int>(std::lround(k * (n - 1) / 3.0)));
    if (!opt.us_views.empty()) {
      us_anatomy = std::make_unique<us::UltrasoundAnatomy>(us->anatomy);
      template_cols = us->template_cols;
      template_rows = us->template_rows;
      plan = us->plan;
      us::UltrasoundSettings set = us->settings;
      set.width = set.height = opt.us_size;
      for (us::PlaneKind k : opt.us_views) imagers.push_back(std::make_unique<us::PlaneImager>(*us_anatomy, set, k));
    }
  }
};

FrameRecorder::FrameRecorder(const Model& model, FrameOptions opt, const UltrasoundInput* us, std::unique_ptr<SnapshotDose> dose)
    : impl_(std::make_unique<Impl>(model, std::move(opt), us, std::move(dose))) {
  for (render::View v : impl_->opt.views) fs::create_directories(fs::path(impl_->opt.out_dir) / render::view_name(v));
  for (us::PlaneKind k : impl_->opt.us_views) fs::create_directories(fs::path(impl_->opt.out_dir) / us_view_name(k));
}

FrameRecorder::~FrameRecorder() = default;

const std::string& FrameRecorder::backend() const { return impl_->ctx.backend(); }

void FrameRecorder::observe(const Snapshot& snap) {
  Impl& im = *impl_;
  if (im.tool_names.empty())
    for (const auto& t : snap.tools) im.tool_names.emplace_back(t.name.data());
  char line[320];
  for (const SnapshotEvent& e : snap.events) {
    const char* tool = e.tool >= 0 && e.tool < static_cast<int>(im.tool_names.size()) ? im.tool_names[e.tool].c_str() : "-";
    std::snprintf(line, sizeof line, "t=%8.4f s  %-10s %-60s depth %6.1f mm  force %6.2f N\n", e.time, tool, e.text.data(),
                  e.depth * 1e3, std::abs(e.force) < 0.005 ? 0.0 : e.force);  // not "-0.00 N"
    im.events += line;
    const std::string text = e.text.data();
    if (text.find("puncture") != std::string::npos || text.find("bone") != std::string::npos ||
        text.find("core") != std::string::npos) {
      im.marks.emplace_back(e.depth * 1e3, e.force);
      im.mark_labels.push_back(text);
    }
  }
  if (snap.faulted) {
    std::snprintf(line, sizeof line, "t=%8.4f s  FAULT  %s\n", snap.time, snap.fault.data());
    im.events += line;
  }
  auto first_of = [&](uint8_t carries) {
    const auto it = std::find_if(snap.tools.begin(), snap.tools.end(), [carries](const ToolReadout& t) { return (t.carries & carries) != 0; });
    return it == snap.tools.end() ? nullptr : &*it;
  };
  if (const ToolReadout* f = first_of(kCarriesVolume)) {
    im.fill_t.push_back(snap.time);
    im.fill_ml.push_back(f->value * 1e6);
  }
  if (const ToolReadout* p = first_of(kCarriesImaging)) {
    im.probe_t.push_back(snap.time);
    im.probe_n.push_back(p->force);
  }
  for (const ToolReadout& t : snap.tools)
    if ((t.carries & kCarriesInsertion) && t.active && t.depth > 0.0) {
      im.t.push_back(snap.time);
      im.depth.push_back(t.depth * 1e3);
      im.force.push_back(t.force);
      break;
    }
}

void FrameRecorder::add_frame(const Snapshot& snap) {
  Impl& im = *impl_;
  im.renderer.update(snap);
  // the implant's dose at this frame: the isodose surface in 3D, the lines on the TRUS planes
  std::shared_ptr<const dosimetry::DoseField> field;
  if (im.dose) {
    const int seeds = im.dose->update(snap).indices.seeds;
    if (seeds > 0) field = im.dose->field();
    if (!im.opt.views.empty())
      im.renderer.set_isodose(field ? dosimetry::isodose_surface(*field, field->prescription_gy, dosimetry::kViewSurfaceStride) : dosimetry::IsoSurface{});
  }
  std::vector<uint8_t> rgb;
  for (size_t v = 0; v < im.opt.views.size(); ++v) {
    const auto t0 = std::chrono::steady_clock::now();
    const render::View view = im.opt.views[v];
    render::RenderOptions ro;
    ro.displacement = im.opt.displacement;
    ro.displacement_max_mm = im.opt.displacement_max_mm;
    ro.title = im.renderer.scene().name + "  [" + render::view_name(view) + "]";
    im.target.bind();
    im.renderer.render(render::preset_camera(view, im.renderer.scene(), &snap, im.orbit), im.opt.width, im.opt.height, ro);
    rgb = im.queue.take_buffer();
    im.target.read_rgb(rgb);
    im.render_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (v == 0 && std::find(im.thumb_frames.begin(), im.thumb_frames.end(), im.frame) != im.thumb_frames.end() &&
        im.thumbs.size() < 4)
      im.thumbs.push_back(make_thumb(rgb, im.opt.width, im.opt.height, 640, snap.time));
    char name[64];
    std::snprintf(name, sizeof name, "frame_%06d.png", im.frame);
    const fs::path path = fs::path(im.opt.out_dir) / render::view_name(view) / name;
    im.queue.push(path.string(), im.opt.width, im.opt.height, std::move(rgb), 3, im.aa == render::Antialias::Fxaa);
  }
  if (!im.imagers.empty()) {
    // the probe as the snapshot shows it; a snapshot without one keeps the last pose seen
    us::probe_view_from_snapshot(snap, im.probe_view);
    us::scene_from_snapshot(snap, im.probe_view, im.us_scene);
    for (size_t v = 0; v < im.imagers.size(); ++v) {
      const auto t0 = std::chrono::steady_clock::now();
      const us::UsImage& img = im.imagers[v]->render(im.us_scene);
      std::vector<uint8_t> gray = im.queue.take_buffer();
      gray.assign(img.pixels.begin(), img.pixels.end());
      int channels = 1;
      if (im.dose) {  // a scene with seeds: RGB frames, the isodose lines once a seed is in
        im.iso_segments.clear();
        if (field) plane_isodose_lines(*field, pixel_plane(*im.imagers[v], im.probe_view), im.iso_segments);
        std::vector<uint8_t> colour = im.queue.take_buffer();
        draw_isodose_rgb(gray, img.width, img.height, im.iso_segments, colour);
        std::swap(gray, colour);
        channels = 3;
      }
      // the template's labelled grid on the transverse plane (the imager drew its crosses)
      if (im.template_cols > 0 && im.imagers[v]->kind() == us::PlaneKind::Transverse && im.imagers[v]->settings().overlays) {
        const HoleMarks marks =
            transverse_hole_marks(pixel_plane(*im.imagers[v], im.probe_view),
                                  template_holes_from_draw(snap.draw, im.template_cols, im.template_rows, im.probe_view.axis));
        if (channels == 3) draw_template_rgb(gray, img.width, img.height, marks, im.template_cols, im.template_rows, im.plan);
        else draw_template_gray(gray, img.width, img.height, marks, im.template_cols, im.template_rows, im.plan);
      }
      im.us_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (v == 0 && im.opt.views.empty() && im.thumbs.size() < 4 &&
          std::find(im.thumb_frames.begin(), im.thumb_frames.end(), im.frame) != im.thumb_frames.end()) {
        std::vector<uint8_t> rgb3 = channels == 3 ? gray : std::vector<uint8_t>(3 * gray.size());
        if (channels == 1)
          for (size_t i = 0; i < gray.size(); ++i) rgb3[3 * i] = rgb3[3 * i + 1] = rgb3[3 * i + 2] = gray[i];
        im.thumbs.push_back(make_thumb(rgb3, img.width, img.height, 320, snap.time));
      }
      char name[64];
      std::snprintf(name, sizeof name, "frame_%06d.png", im.frame);
      const fs::path path = fs::path(im.opt.out_dir) / us_view_name(im.opt.us_views[v]) / name;
      im.queue.push(path.string(), img.width, img.height, std::move(gray), channels);
    }
  }
  ++im.frame;
}

void FrameRecorder::progress(int i, int n, double sim_time) const {
  if (!impl_->opt.progress || n <= 0) return;
  const bool tty = ::isatty(2);
  const int pct = static_cast<int>(100.0 * i / n);
  if (!tty && i != n && (i % std::max(1, n / 10)) != 0) return;
  const int width = 30, filled = width * i / n;
  std::fprintf(stderr, "%s[%.*s%*s] %3d%%  frame %d/%d  t = %.3f s%s", tty ? "\r" : "", filled,
               "##############################", width - filled, "", pct, i, n, sim_time, tty ? (i == n ? "\n" : "") : "\n");
  std::fflush(stderr);
}

FrameSummary FrameRecorder::finish(const std::string& extra_json) {
  Impl& im = *impl_;
  im.queue.finish();
  const fs::path dir(im.opt.out_dir);
  write_file_atomic((dir / "events.log").string(), im.events.empty() ? std::string("(no events)\n") : im.events);
  std::string csv = "t_s,depth_mm,force_n\n";
  char line[96];
  for (size_t k = 0; k < im.t.size(); ++k) {
    std::snprintf(line, sizeof line, "%.6f,%.4f,%.5f\n", im.t[k], im.depth[k], im.force[k]);
    csv += line;
  }
  write_file_atomic((dir / "force_depth.csv").string(), csv);
  ContactSheetInput in;
  in.title = im.renderer.scene().name;
  in.thumbs = im.thumbs;
  in.depth_mm = im.depth;
  in.force_n = im.force;
  in.marks = im.marks;
  // no needle samples: the filling's volume if it changed, else the probe's contact force
  const bool filled = !im.fill_ml.empty() && *std::max_element(im.fill_ml.begin(), im.fill_ml.end()) >
                                                 *std::min_element(im.fill_ml.begin(), im.fill_ml.end());
  if (filled) in.over_time = {"filled volume", "target volume of the filled organ [ml]", im.fill_t, im.fill_ml};
  else if (!im.probe_t.empty()) in.over_time = {"probe contact force", "tissue force on the probe [N]", im.probe_t, im.probe_n};
  write_contact_sheet((dir / "contact_sheet.png").string(), in);

  FrameSummary s;
  s.frames = im.frame;
  s.files = im.queue.written();
  std::vector<double> ms = im.render_ms;
  if (!ms.empty()) {
    std::sort(ms.begin(), ms.end());
    s.render_ms_median = ms[ms.size() / 2];
    s.render_ms_max = ms.back();
  }
  s.backend = im.ctx.backend();
  s.gl_renderer = im.ctx.renderer();
  nlohmann::json j = nlohmann::json::parse(extra_json);
  j["frames_per_view"] = s.frames;
  j["png_files"] = s.files;
  nlohmann::json views = nlohmann::json::array();
  for (render::View v : im.opt.views) views.push_back(render::view_name(v));
  for (us::PlaneKind k : im.opt.us_views) views.push_back(us_view_name(k));
  j["views"] = views;
  j["width_px"] = im.opt.width;
  j["height_px"] = im.opt.height;
  j["fps"] = im.opt.fps;
  j["antialias"] = render::antialias_name(im.aa);
  j["events"] = std::count(im.events.begin(), im.events.end(), '\n');
  j["gl_backend"] = s.backend;
  j["gl_renderer"] = s.gl_renderer;
  j["render_ms_median"] = s.render_ms_median;
  j["render_ms_max"] = s.render_ms_max;
  if (!im.us_ms.empty()) {
    std::vector<double> u = im.us_ms;
    std::sort(u.begin(), u.end());
    j["ultrasound_ms_median"] = u[u.size() / 2];
    j["ultrasound_px"] = im.opt.us_size;
  }
  write_file_atomic((dir / "summary.json").string(), j.dump(2) + "\n");
  return s;
}

}  // namespace ps::frames
