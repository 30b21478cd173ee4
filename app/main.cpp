// prostatesim: the one executable. Subcommands in app/cmd_*.cpp.
#include <spdlog/spdlog.h>

#include <exception>

#include "app/commands.h"
#include "app/frames/replay_frames.h"
#include "app/run_session.h"
#if PROSTATESIM_HAVE_GUI
#include "app/gui/trainee_window.h"
#endif
#include "engine/util/error.h"

int main(int argc, char** argv) {
  CLI::App app{"ProstateSim: prostate biopsy and brachytherapy simulator (discrete shape-memory tissue model)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "prostatesim 0.1");
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "log progress to stderr");
  ps::app::Runner run;
  ps::app::add_simulate_command(app, run);
  ps::app::add_check_command(app, run);
  ps::app::add_validate_command(app, run);
  ps::app::add_make_anatomy_command(app, run);
  ps::app::add_insert_command(app, run);
  // frontends (window, PNG frames) register in app/run_session.h before these two are added
  ps::app::register_replay_frames(ps::frames::replay_frames_frontend());
#if PROSTATESIM_HAVE_GUI
  ps::app::register_window_frontend(&ps::gui::run_window);
#endif
  ps::app::add_run_command(app, run);
  ps::app::add_replay_command(app, run);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : ps::app::kExitBadInput;
  }
  spdlog::set_level(verbose ? spdlog::level::info : spdlog::level::warn);
  spdlog::set_pattern("%v");
  try {
    return run();
  } catch (const ps::InputError& e) {
    spdlog::error("error: {}", e.what());
    return ps::app::kExitBadInput;
  } catch (const ps::CompileError& e) {
    spdlog::error("error: {}", e.what());
    return ps::app::kExitBadInput;
  } catch (const std::exception& e) {
    spdlog::error("error: {}", e.what());
    return ps::app::kExitBadInput;
  }
}
