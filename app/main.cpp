// prostatesim: the one executable. Subcommands in app/cmd_*.cpp.
#include <spdlog/spdlog.h>

#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include "app/commands.h"
#include "app/frames/replay_frames.h"
#include "app/core/run_session.h"
#if PROSTATESIM_HAVE_GUI
#include "app/gui/trainee_window.h"
#endif
#include "engine/util/error.h"
#include "engine/util/sim_fault.h"
#include "render/render_error.h"

int main(int argc, char** argv) {
  CLI::App app{"ProstateSim: prostate biopsy and brachytherapy simulator (discrete shape-memory tissue model)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("prostatesim ") + ps::app::kVersion);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "log progress to stderr");
  ps::app::Runner run;
  ps::app::add_simulate_command(app, run);
  ps::app::add_check_command(app, run);
  ps::app::add_validate_command(app, run);
  ps::app::add_make_anatomy_command(app, run);
  ps::app::add_insert_command(app, run);
  ps::app::add_ultrasound_command(app, run);
  ps::app::add_report_command(app, run);
  ps::app::add_stress_command(app, run);
  ps::app::add_bench_command(app, run);
  ps::app::add_edit_command(app, run);
  ps::app::add_dose_command(app, run);
  ps::app::add_plan_command(app, run);
  // frontends (window, PNG frames) register in app/core/run_session.h before these two are added
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
  } catch (const ps::CompileError& e) {  // degenerate geometry in the scenario's meshes
    spdlog::error("error: {}", e.what());
    return ps::app::kExitBadInput;
  } catch (const ps::SimulationFault& e) {
    spdlog::error("simulation fault: {}", e.what());
    return ps::app::kExitFault;
  } catch (const std::filesystem::filesystem_error& e) {  // an output path the user gave
    spdlog::error("error: {}", e.what());
    return ps::app::kExitBadInput;
  } catch (const ps::render::RenderError& e) {  // no headless GL / no display: the machine, not a bug
    spdlog::error("error: {}", e.what());
    return ps::app::kExitBadInput;
  } catch (const std::bad_alloc&) {
    spdlog::error("error: out of memory (the scene is too large for this machine; raise spacing_mm)");
    return ps::app::kExitInternal;
  } catch (const std::exception& e) {
    // logic_error, out_of_range, ... from inside the program: a bug, not bad input.
    spdlog::error("{}", ps::app::internal_fault_message(e.what(), argc, argv));
    return ps::app::kExitInternal;
  } catch (...) {
    spdlog::error("{}", ps::app::internal_fault_message("unknown exception", argc, argv));
    return ps::app::kExitInternal;
  }
}

std::string ps::app::internal_fault_message(const std::string& what, int argc, char** argv) {
  std::string cmd;
  for (int i = 0; i < argc; ++i) cmd += (i ? " " : "") + std::string(argv[i]);
  return "internal error: " + what +
         "\nThis is a bug in ProstateSim, not a problem with your input. Please report it with the scenario "
         "file(s) named below and this version:\n  version: prostatesim " + std::string(kVersion) +
         "\n  command: " + cmd;
}
