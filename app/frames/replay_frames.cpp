#include "app/frames/replay_frames.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "engine/io/instruments_csv.h"
#include "engine/util/error.h"
#include "engine/ultrasound/from_simulation.h"
#include "render/render_scene.h"
#include "engine/tools/needle/needle.h"

namespace ps::frames {

ReplayFramesResult replay_frames(const Scene& scene, LockstepRunner& run, int64_t end_tick, FrameOptions opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const double dt = scene.model->dt;
  if (!(opt.fps > 0.0 && opt.fps <= 1000.0)) throw InputError("", 0, "--fps", "must be in (0, 1000] frames per simulated second");
  // a frame every `every` ticks: the simulated frame interval rounded to whole ticks
  const int64_t every = std::max<int64_t>(1, std::llround(1.0 / (opt.fps * dt)));
  const int64_t start = run.tick();
  end_tick = std::max(end_tick, start);
  const int frames = static_cast<int>((end_tick - start) / every) + 1 + ((end_tick - start) % every ? 1 : 0);
  opt.expected_frames = frames;
  std::unique_ptr<UltrasoundInput> us;
  if (!opt.us_views.empty()) {
    if (!scene.spec.probe) throw InputError(scene.spec.file, 0, "--views", "ultrasound views need a scenario with a probe: section");
    us = std::make_unique<UltrasoundInput>();
    us->anatomy = us::anatomy_for_scenario(scene.spec, *scene.model);
    us->settings = us::settings_for_probe(*scene.spec.probe);
    if (scene.spec.probe->has_template) {
      us->template_cols = scene.spec.probe->template_cols;
      us->template_rows = scene.spec.probe->template_rows;
      us->plan = planned_holes(scene.spec);
    }
  }
  // a scene with seeds: the isodose surface and lines (a scene without a gland: none)
  std::unique_ptr<SnapshotDose> dose;
  if (SnapshotDose::scene_has_seeds(scene)) {
    try {
      dose = std::make_unique<SnapshotDose>(scene);
    } catch (const InputError&) {
      dose.reset();
    }
  }
  opt.shapes = anatomy::display_meshes_for_scenario(scene.spec, *scene.model);
  FrameRecorder rec(*scene.model, opt, us.get(), std::move(dose));  // GL context first, then the folder
  ReplayFramesResult r;
  InstrumentsCsv instruments;  // instruments.csv: the needles' and the probe's poses at every frame
  int done = 0;
  {
    const Snapshot& s = run.snapshot();
    rec.observe(s);
    rec.add_frame(s);
    instruments.add(scene);
    rec.progress(++done, frames, s.time);
  }
  while (run.tick() < end_tick) {
    if (!run.step()) {
      r.faulted = true;
      break;
    }
    const Snapshot& s = run.snapshot();
    rec.observe(s);
    if ((run.tick() - start) % every == 0 || run.tick() == end_tick) {
      rec.add_frame(s);
      instruments.add(scene);
      rec.progress(++done, frames, s.time);
    }
  }
  if (r.faulted) {
    const Snapshot& s = run.snapshot();
    r.fault = s.fault.data();
    rec.observe(s);
    rec.add_frame(s);  // the state at the fault, for the record
    instruments.add(scene);
    rec.progress(frames, frames, s.time);
  }
  r.ticks = run.tick();
  nlohmann::json j;
  j["scenario"] = scene.spec.name;
  j["ticks"] = r.ticks;
  j["sim_time_s"] = static_cast<double>(r.ticks) * dt;
  j["frame_every_ticks"] = every;
  j["faulted"] = r.faulted;
  if (r.faulted) j["fault"] = r.fault;
  r.summary = rec.finish(j.dump());
  if (scene.tools.has<NeedleTool>()) instruments.write(opt.out_dir + "/instruments.csv");
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

namespace {

struct Args {
  std::string out, size = "1280x720", views = "3d", aa = "auto";
  double fps = 30.0;
  bool force = false, displacement = false;
} g_args;

void add_options(CLI::App& sub) {
  sub.add_option("--out", g_args.out, "write PNG frames, events.log, force_depth.csv, summary.json and contact_sheet.png here");
  sub.add_option("--size", g_args.size, "frame size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub.add_option("--fps", g_args.fps, "frames per simulated second")->capture_default_str();
  sub.add_option("--views", g_args.views, "comma-separated: 3d, anterior, lateral, probe, needle, us_transverse, us_sagittal (simulated TRUS, 512x512 grayscale)")->capture_default_str();
  sub.add_flag("--force", g_args.force, "replace a previous replay in a non-empty --out folder");
  sub.add_flag("--displacement", g_args.displacement, "colour the organs by displacement [mm]");
  sub.add_option("--aa", g_args.aa,
                 "antialiasing: auto (msaa on a hardware GL, fxaa on a software rasteriser), msaa (4x), fxaa, none")
      ->capture_default_str();
}

bool wanted() { return !g_args.out.empty(); }

int run(app::ReplaySession& s) {
  FrameOptions opt;
  parse_size(g_args.size, opt.width, opt.height);
  opt.views = parse_views(g_args.views, &opt.us_views);
  opt.fps = g_args.fps;
  opt.out_dir = g_args.out;
  opt.force = g_args.force;
  opt.displacement = g_args.displacement;
  opt.antialias = parse_antialias_option(g_args.aa);
  const ReplayFramesResult r = replay_frames(s.scene, s.runner, s.end_tick, opt);
  std::printf("frames: %s/{%s}/frame_*.png (%d per view, %dx%d), contact sheet %s/contact_sheet.png, events %s/events.log\n",
              opt.out_dir.c_str(), g_args.views.c_str(), r.summary.frames, opt.width, opt.height, opt.out_dir.c_str(), opt.out_dir.c_str());
  std::printf("render %.1f ms per view-frame (median, %s %s), %.1f s wall\n", r.summary.render_ms_median, r.summary.backend.c_str(),
              r.summary.gl_renderer.c_str(), r.wall_s);
  return 0;  // a fault is reported by the replay command after this
}

}  // namespace

app::ReplayFrames replay_frames_frontend() { return {&add_options, &wanted, &run}; }

}  // namespace ps::frames
