// `prostatesim ultrasound SCENARIO --out DIR [--time S] [--views us_transverse,us_sagittal]`:
// settles the scene for the given simulated time (probe and needle scripts run), then writes the
// simulated TRUS planes (engine/ultrasound/) as grayscale PNG: DIR/us_transverse.png and
// DIR/us_sagittal.png. Scanner settings (gain, depth, frequency, geometry) are checked before
// anything runs: a nonsensical value exits 2 naming the field, nothing written.
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/cli_ranges.h"
#include "app/commands.h"
#include "app/frames/template_overlay.h"
#include "app/frames/us_isodose.h"
#include "app/output_paths.h"
#include "engine/io/png_write.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/ultrasound/imager.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {
struct UltrasoundArgs {
  std::string scenario;
  std::string out = "out/ultrasound";
  double time = 0.0;
  std::string views = "us_transverse,us_sagittal";
  double gain_db = 0.0, depth_mm = 60.0, frequency_mhz = 7.5, dynamic_range_db = 60.0;
  double fov_deg = 140.0, width_mm = 60.0, slice_mm = 1.5;
  // the point-spread function's defaults are the imager's (engine/ultrasound/settings.h)
  inline static const us::UltrasoundSettings kDefault{};
  double bandwidth = kDefault.bandwidth, focus_mm = kDefault.focus_depth * 1e3, f_number = kDefault.f_number;
  double rx_aperture_mm = kDefault.rx_aperture * 1e3;
  double radius_mm = -1.0;         // convex radius: default the probe's radius
  double transverse_back_mm = 0.0, linear_front_mm = 0.0;
  int size = 512;
  bool no_overlays = false;
  std::string grid = "auto";       // template grid overlay: auto (when needles carry seeds), on, off
};
}  // namespace

void add_ultrasound_command(CLI::App& app, Runner& run) {
  auto a = std::make_shared<UltrasoundArgs>();
  CLI::App* sub = app.add_subcommand("ultrasound", "settle a scenario and write its simulated TRUS planes as PNG");
  sub->add_option("scenario", a->scenario, "scenario YAML file with a probe: section")->required();
  sub->add_option("--out", a->out, "output folder (created)")->capture_default_str();
  sub->add_option("--time", a->time, "simulated time before imaging [s]")
      ->check(in_range(0.0, ScenarioSpec::kMaxDuration, "s"))
      ->capture_default_str();
  sub->add_option("--views", a->views, "comma-separated: us_transverse, us_sagittal")->capture_default_str();
  sub->add_option("--gain-db", a->gain_db, "overall gain [dB]")->capture_default_str();
  sub->add_option("--depth-mm", a->depth_mm, "imaging depth [mm]")->capture_default_str();
  sub->add_option("--frequency-mhz", a->frequency_mhz, "centre frequency [MHz]")->capture_default_str();
  sub->add_option("--dynamic-range-db", a->dynamic_range_db, "log-compression range [dB]")->capture_default_str();
  sub->add_option("--fov-deg", a->fov_deg, "transverse sector angle [deg]")->capture_default_str();
  sub->add_option("--width-mm", a->width_mm, "sagittal linear array length [mm]")->capture_default_str();
  sub->add_option("--radius-mm", a->radius_mm, "transverse convex radius [mm] (default: the probe's radius)");
  sub->add_option("--transverse-back-mm", a->transverse_back_mm, "transverse plane behind the probe's tip centre [mm]")
      ->capture_default_str();
  sub->add_option("--linear-front-mm", a->linear_front_mm, "front end of the linear array behind the tip centre [mm]")
      ->capture_default_str();
  sub->add_option("--slice-mm", a->slice_mm, "elevation slice thickness, FWHM [mm]")->capture_default_str();
  sub->add_option("--bandwidth", a->bandwidth, "pulse-echo -6 dB fractional bandwidth (axial resolution)")->capture_default_str();
  sub->add_option("--focus-mm", a->focus_mm, "transmit focal depth [mm]")->capture_default_str();
  sub->add_option("--f-number", a->f_number, "transmit f-number")->capture_default_str();
  sub->add_option("--rx-aperture-mm", a->rx_aperture_mm, "receive aperture [mm]")->capture_default_str();
  sub->add_option("--size", a->size, "image width and height [px]")->capture_default_str();
  sub->add_flag("--no-overlays", a->no_overlays, "no biopsy guide line or template grid");
  sub->add_option("--grid", a->grid, "template grid overlay: auto | on | off")->capture_default_str();
  sub->callback([a, &run] {
    run = [a]() -> int {
      // views and settings first: bad input exits 2 before anything runs or is written
      bool want[2] = {false, false};
      {
        std::stringstream ss(a->views);
        std::string v;
        while (std::getline(ss, v, ',')) {
          if (v == "us_transverse") want[0] = true;
          else if (v == "us_sagittal") want[1] = true;
          else throw InputError("", 0, "--views", "unknown view '" + v + "' (us_transverse, us_sagittal)");
        }
        if (!want[0] && !want[1]) throw InputError("", 0, "--views", "no view named");
      }
      const ScenarioSpec spec = parse_scenario_file(a->scenario);
      if (!spec.probe) throw InputError(spec.file, 0, "probe", "the scenario has no probe: section to image from");
      us::UltrasoundSettings set = us::settings_for_probe(*spec.probe);
      set.gain_db = a->gain_db;
      set.depth = a->depth_mm * 1e-3;
      set.frequency = a->frequency_mhz * 1e6;
      set.dynamic_range_db = a->dynamic_range_db;
      set.fov = a->fov_deg * 3.141592653589793 / 180.0;
      set.linear_width = a->width_mm * 1e-3;
      if (a->radius_mm > 0 || a->radius_mm == 0) set.convex_radius = a->radius_mm * 1e-3;
      set.slice_thickness = a->slice_mm * 1e-3;
      set.bandwidth = a->bandwidth;
      set.focus_depth = a->focus_mm * 1e-3;
      set.f_number = a->f_number;
      set.rx_aperture = a->rx_aperture_mm * 1e-3;
      set.transverse_back = a->transverse_back_mm * 1e-3;
      set.linear_front = a->linear_front_mm * 1e-3;
      set.width = set.height = a->size;
      set.overlays = !a->no_overlays;
      us::validate(set, "command line");
      if (a->grid != "auto" && a->grid != "on" && a->grid != "off")
        throw InputError("", 0, "--grid", "expected auto, on or off, got '" + a->grid + "'");

      auto model = compile_scenario(spec);
      auto probe_tool = make_probe_tool(spec, *model);
      ProbeTool* probe = probe_tool.get();
      auto needle_tool = make_needle_tool(model, spec.needles);
      NeedleTool* needles = needle_tool.get();
      bool seeds = false;
      for (const auto& n : spec.needles.needles) seeds = seeds || !n.seed_depths.empty();
      for (const auto& w : model->compile_warnings) spdlog::warn("warning: {}", w);
      Simulation sim(model);
      sim.add_tool(std::move(probe_tool));
      if (needle_tool) sim.add_tool(std::move(needle_tool));
      prepare_output_dir(a->out, "--out");  // after compiling (bad input writes nothing), before the run
      const long ticks = std::lround(a->time / model->dt);
      for (long i = 0; i < ticks; ++i)
        if (!sim.tick()) {
          spdlog::error("error: simulation stopped: {}", sim.state().fault.describe(*model));
          return kExitFault;
        }

      const us::UltrasoundAnatomy anatomy = us::anatomy_for_scenario(spec, *model);
      us::UltrasoundScene scene;
      us::SceneOptions opt;
      opt.grid = a->grid == "on" || (a->grid == "auto" && seeds);
      us::scene_from_state(sim.state(), probe, needles, opt, scene);
      const char* names[2] = {"us_transverse", "us_sagittal"};
      for (int v = 0; v < 2; ++v) {
        if (!want[v]) continue;
        us::PlaneImager im(anatomy, set, v == 0 ? us::PlaneKind::Transverse : us::PlaneKind::Sagittal);
        const us::UsImage& img = im.render(scene);
        const std::string path = a->out + "/" + names[v] + ".png";
        std::vector<uint8_t> gray = img.pixels;
        // the template's labelled grid with its crosses (frames/template_overlay.h)
        if (v == 0 && opt.grid && set.overlays && spec.probe->has_template) {
          std::vector<frames::TemplateHole> holes;
          for (int r = 0; r < spec.probe->template_rows; ++r)
            for (int c = 0; c < spec.probe->template_cols; ++c) {
              const NeedlePath h = probe->template_hole(c, r);
              holes.push_back({c, r, h.entry, h.direction});
            }
          const frames::HoleMarks marks = frames::transverse_hole_marks(frames::pixel_plane(im, scene.probe), holes);
          frames::draw_template_gray(gray, img.width, img.height, marks, spec.probe->template_cols, spec.probe->template_rows,
                                     frames::planned_holes(spec));
        }
        write_png_atomic(path, img.width, img.height, 1, gray.data());
        std::printf("%s: %dx%d px, %.3f mm/px, t = %.3f s -> %s\n", names[v], img.width, img.height, img.pixel * 1e3,
                    sim.state().time, path.c_str());
      }
      return kExitOk;
    };
  });
}

}  // namespace ps::app
