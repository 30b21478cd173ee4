// `prostatesim edit [SCENARIO] [--set KEY=VALUE]... [--save | --save-as FILE] [--frames N]
//                   [--screenshot PNG] [--preview S]`: the instructor's scenario editor window (app/editor/).
// A build without the window libraries (-DPROSTATESIM_GUI=OFF) says so and exits 2.
#include <spdlog/spdlog.h>

#include "app/cli_ranges.h"
#include "app/commands.h"
#if PROSTATESIM_HAVE_EDITOR
#include "app/editor/editor_window.h"
#endif

namespace ps::app {

void add_edit_command(CLI::App& app, Runner& run) {
  struct Args {
    std::string scenario, save_as, screenshot;
    std::vector<std::string> sets;
    bool save = false;
    int frames = -1;
    double preview = 0.0;
  };
  auto a = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("edit", "instructor scenario editor window (materials, lesions, targets, filling, probe, needle plan)");
  sub->add_option("scenario", a->scenario, "scenario YAML file to open")->check(CLI::ExistingFile);
  sub->add_option("--set", a->sets, "KEY=VALUE edit applied at start (key path, YAML value in file units), repeatable");
  sub->add_flag("--save", a->save, "save the file after the --set edits (atomically)");
  sub->add_option("--save-as", a->save_as, "save to this file instead");
  sub->add_option("--frames", a->frames, "close the window after N frames (scripted use, tests)")->check(in_range(1, 1e9, "frames"));
  sub->add_option("--screenshot", a->screenshot, "PNG of the window's last frame");
  sub->add_option("--preview", a->preview, "run the in-place preview this long [s] at the first frame and print its state hash")
      ->check(simulated_seconds());
  sub->callback([a, &run] {
    run = [a]() -> int {
#if PROSTATESIM_HAVE_EDITOR
      ps::editor::EditorArgs e;
      e.scenario = a->scenario;
      e.sets = a->sets;
      e.save = a->save;
      e.save_as = a->save_as;
      e.frames = a->frames;
      e.screenshot = a->screenshot;
      e.preview_s = a->preview;
      return ps::editor::run_editor(e);
#else
      spdlog::error("error: `prostatesim edit` needs the GUI build (this binary was built with -DPROSTATESIM_GUI=OFF: no GLFW / Dear ImGui)");
      return kExitBadInput;
#endif
    };
  });
}

}  // namespace ps::app
