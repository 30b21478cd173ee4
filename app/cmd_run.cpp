// `prostatesim run SCENARIO [--script F] [--record FILE] [--headless] [--duration S] [--hash]
//                           [--factor X] [--unpaced] [--report DIR [--trainee T] [--session S]]
//                           [--state FILE]`
// Runs the scene on the real-time physics thread (engine/realtime/physics_loop.h). With a
// registered window frontend and a display (and no --headless) the trainee window drives it;
// otherwise it runs headless for --duration (default: the script's, else the scenario's).
// --record writes every applied command with its tick (engine/realtime/recording.h); at the end
// the state hash is printed (16 hex digits; the same as `replay --hash` of the recording).
// --report DIR: the session report at the end (metrics.json with its score, report.png, the
// force-depth and event CSVs; app/session/session_capture.h), fed after every tick outside the step.
// Bad input (scenario, script, options) exits 2 before anything is written.
// Recovery (issue 14): a simulation fault (NaN, blow-up, a watchdog finding) stops the physics,
// never the program: the fault is printed with its tick, time and particle, the recording is
// still finished (the session is kept), the last good state is written atomically with
// --save-on-fault FILE, and the exit code is 3. The window shows the fault and offers to save
// the last good state and to restart. An exception on the physics thread (a bug) is caught there
// and reported as an internal error (exit 4), after the recording is finished.
// --state FILE goes on from a saved state (engine/realtime/state_file.h) of this very scenario
// file: the run starts at the state's tick, the script's commands before it are skipped, and
// --duration stays the simulated time at which the run ends. A state of another scenario (or of
// an edited file) or a damaged one exits 2 naming the file, line and field; not with --record or
// --report (they cover a session from the start).
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <stdexcept>

#include "app/cli_ranges.h"
#include "app/commands.h"
#include "app/output_paths.h"
#include "app/core/run_session.h"
#include "app/session/session_capture.h"
#include "engine/realtime/state_file.h"
#include "engine/sim/watchdog.h"
#include "engine/util/error.h"
#include "haptics/probe_source.h"
#include "haptics/spacemouse.h"
#if PROSTATESIM_IGTL
#include "igtl/server.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/needle/needle.h"
#endif

namespace ps::app {

namespace {
struct RunArgs {
  std::string scenario, script, record, device = "auto", probe_device = "none", save_on_fault, inject, state;
  std::string report, trainee, session;
  bool headless = false, hash_only = false, unpaced = false, no_watchdog = false;
  double duration = -1.0, factor = 1.0;
  int igtl_port = -1;              // --igtl-port: -1 off
};

bool have_display() {
  const char* d = std::getenv("DISPLAY");
  const char* w = std::getenv("WAYLAND_DISPLAY");
  return (d && *d) || (w && *w);
}
}  // namespace


int run_live(const RunArgs& a) {
  Scene scene = load_scene(a.scenario);
  const Model& m = *scene.model;
  std::unique_ptr<Script> script;
  std::unique_ptr<CommandPlayer> player;
  if (!a.script.empty()) {
    script = std::make_unique<Script>(parse_script_file(a.script));
    player = std::make_unique<CommandPlayer>(script_commands(*script, scene));
  }
  const WindowFrontend window = window_frontend();
  const bool windowed = window && !a.headless && have_display();
  double duration = a.duration;
  if (duration <= 0 && !windowed) duration = script && script->duration > 0 ? script->duration : m.duration;
  const int64_t end_tick = duration > 0 ? static_cast<int64_t>(std::llround(duration / m.dt)) : -1;

  // --state FILE: go on from a saved state (read and checked before anything runs)
  SavedState start_state;
  if (!a.state.empty()) {
    if (!a.record.empty() || !a.report.empty())
      throw InputError(a.state, 0, "--state", "--record and --report cover a session from the scenario's start; not with --state");
    start_state = read_state_file(a.state);
    check_state_matches(start_state, scene.spec.name, scene.content_hash);
  }

  std::unique_ptr<SessionCapture> capture;
  if (!a.report.empty()) {
    capture = SessionCapture::make(scene);
    if (!capture) throw InputError(a.scenario, 0, "--report", "the scenario has no needles: section (nothing to score)");
    prepare_output_dir(a.report, "--report");
  }
  std::unique_ptr<RecordingWriter> rec;
  const FaultInjection inject = parse_fault_injection(a.inject);
  if (!a.record.empty()) rec = std::make_unique<RecordingWriter>(a.record, RecordingHeader{scene.spec.name, scene.content_hash, m.dt, m.substeps});

  // the device that drives the active needle: a script, the SpaceMouse (when spacenavd runs), or
  // the window's mouse and keyboard
  std::unique_ptr<haptics::SpaceMouseDevice> spacemouse;
  std::unique_ptr<haptics::MouseKeyboardDevice> mouse;
  std::unique_ptr<haptics::DeviceSource> device;
  if (a.device == "spacemouse" || (a.device == "auto" && !player && windowed)) {
    auto sm = std::make_unique<haptics::SpaceMouseDevice>();
    std::string why;
    if (sm->open(why)) spacemouse = std::move(sm);
    else if (a.device == "spacemouse") spdlog::warn("{}", why);
  }
  if (spacemouse) device = std::make_unique<haptics::DeviceSource>(scene, *spacemouse);
  else if (windowed && !player && a.device != "none" && a.probe_device != "mouse") {
    mouse = std::make_unique<haptics::MouseKeyboardDevice>();
    device = std::make_unique<haptics::DeviceSource>(scene, *mouse);
  }
  // the probe from a device (--probe-device): the SpaceMouse's six axes, or the mouse+keyboard
  // bindings of haptics/probe_source.h; a missing SpaceMouse is said and the probe stays put
  std::unique_ptr<haptics::SpaceMouseDevice> probe_spacemouse;
  std::unique_ptr<haptics::ProbeSource> probe_device;
  if (a.probe_device != "none" && !scene.tools.has<ProbeTool>()) spdlog::warn("--probe-device {}: the scene has no probe", a.probe_device);
  else if (a.probe_device == "spacemouse" && !spacemouse) {
    auto sm = std::make_unique<haptics::SpaceMouseDevice>();
    std::string why;
    if (sm->open(why)) probe_spacemouse = std::move(sm);
    else spdlog::warn("{}", why);
    if (probe_spacemouse) probe_device = std::make_unique<haptics::ProbeSource>(scene, *probe_spacemouse);
  } else if (a.probe_device == "spacemouse" && spacemouse) {
    spdlog::warn("--probe-device spacemouse: the SpaceMouse already drives the needle (--device); the probe stays put");
  } else if (a.probe_device == "mouse") {
    if (!mouse) mouse = std::make_unique<haptics::MouseKeyboardDevice>();
    probe_device = std::make_unique<haptics::ProbeSource>(scene, *mouse);
  }

  LoopOptions opt;
  opt.factor = a.factor;
  opt.stop_at_tick = end_tick;
  opt.as_fast_as_possible = a.unpaced;
  opt.log_timing = true;
  PhysicsLoop loop(*scene.sim, opt);
  if (player) loop.add_source(player.get());
  if (device) loop.add_source(device.get());
  if (probe_device) loop.add_source(probe_device.get());
  if (capture) loop.add_source(capture.get());
  if (rec) {
    loop.applier().set_observer(rec.get());
    loop.set_hash_observer(rec.get(), rec->hash_every());
  }
#if PROSTATESIM_IGTL
  // --igtl-port: poses and TRUS images out, tracked instruments in (igtl/server.h). Without a
  // script, a tracked probe drives the probe unless --probe-device does, and a tracked needle
  // the active needle unless another device does.
  std::unique_ptr<igtl::Server> igtl_server;
  std::unique_ptr<haptics::ProbeSource> igtl_probe;
  std::unique_ptr<haptics::DeviceSource> igtl_needle;
  if (a.igtl_port >= 0) {
    igtl_server = std::make_unique<igtl::Server>(scene, loop, igtl::ServerOptions{a.igtl_port});
    if (!player && !probe_device && scene.tools.has<ProbeTool>()) {
      igtl_probe = std::make_unique<haptics::ProbeSource>(scene, igtl_server->probe_device());
      loop.add_source(igtl_probe.get());
    }
    if (!player && !device && scene.tools.has<NeedleTool>()) {
      igtl_needle = std::make_unique<haptics::DeviceSource>(scene, igtl_server->needle_device());
      loop.add_source(igtl_needle.get());
    }
    // stdout, flushed: a client (or a test) waiting for the port reads this line first
    std::printf("OpenIGTLink: serving on port %d (transforms %s%s, images US_Transverse, US_Sagittal; docs/igtl.md)\n",
                igtl_server->port(), scene.tools.has<ProbeTool>() ? "Probe" : "", scene.tools.has<NeedleTool>() ? ", <needle>Tip" : "");
    std::fflush(stdout);
    igtl_server->start();
  }
#endif
  const Watchdog watchdog(m);
  if (!a.no_watchdog) loop.set_watchdog(&watchdog);
  loop.keep_last_good(true);
  if (inject.tick >= 0) loop.inject_fault(inject.tick, 0, inject.internal);
  if (!a.state.empty()) {
    loop.load_state(start_state);
    if (!a.hash_only)
      std::printf("loaded %s: tick %lld, t=%.4g s, state hash %s\n", a.state.c_str(), static_cast<long long>(start_state.tick),
                  start_state.time, hex16(start_state.state_hash).c_str());
  }
  if (!a.hash_only)
    std::printf("%s: %d particles, tick %.3g ms x %d substeps, %s%s\n", scene.spec.name.c_str(), m.particle_count(), m.dt * 1e3,
                m.substeps, windowed ? "window" : "headless", end_tick >= 0 ? (", " + std::to_string(end_tick) + " ticks").c_str() : "");
  loop.start();
  int rc = kExitOk;
  if (windowed) {
    RunSession session{scene, loop, script.get(), end_tick, a.scenario, mouse.get(), device.get(), rec != nullptr};
    rc = window(session);
  } else {
    loop.wait_for_tick(end_tick);
  }
  loop.stop();
#if PROSTATESIM_IGTL
  if (igtl_server) {
    igtl_server->stop();
    if (!a.hash_only)
      std::printf("OpenIGTLink: %lld transforms and %lld images sent, %lld transforms received\n",
                  static_cast<long long>(igtl_server->transforms_sent()), static_cast<long long>(igtl_server->images_sent()),
                  static_cast<long long>(igtl_server->transforms_received()));
  }
#endif
  const LoopTiming t = loop.timing();
  const int64_t ticks = loop.tick();
  const uint64_t h = scene.sim->hash();
  if (rec) {
    rec->finish(ticks, h, loop.faulted() ? ticks : -1);  // a fault: the tick it happened in
    if (rec->dropped() > 0) {
      spdlog::error("error: {} commands could not be recorded (writer ring full): {} is incomplete", rec->dropped(), a.record);
      rc = kExitFault;
    }
  }
  if (device && device->disconnected()) spdlog::warn("{}", device->status());
  const auto& rr = loop.applier().refusals();
  for (int i = 0; i < rr.size(); ++i) spdlog::warn("{}", rr.at(i).describe());
  if (!a.hash_only)  // commands the tools adjusted to their limits (--hash prints the hash alone)
    for (const std::string& l : scene_tool_reports(scene)) spdlog::warn("{}", l);
  if (a.hash_only) {
    std::printf("%s\n", hex16(h).c_str());
  } else {
    std::printf("%lld ticks, %.4g s simulated; last window: %.0f ticks/s, real-time factor %.3f%s, tick p50 %.3f ms p99 %.3f ms; "
                "whole run: tick p99 %.2f ms max %.2f ms, %lld overruns; %lld commands applied, %lld refused\n",
                static_cast<long long>(ticks), scene.sim->state().time, t.achieved_hz, t.realtime_factor, t.reanchors ? " (slow motion)" : "",
                t.tick_p50_ms, t.tick_p99_ms, t.run_tick_p99_ms, t.run_tick_max_ms, static_cast<long long>(t.overruns),
                static_cast<long long>(loop.applier().applied()), static_cast<long long>(loop.applier().refused()));
    if (rec) std::printf("recorded %s\n", a.record.c_str());
    std::printf("state hash %s\n", hex16(h).c_str());
  }
  if (loop.internal_error()) throw std::logic_error(loop.fault_text());  // main: exit 4, asks for a report
  if (capture) {
    const Score sc = capture->write(a.report, loop.faulted(), a.trainee, a.session);
    if (!a.hash_only) std::printf("score %.1f / 100; wrote %s/{metrics.json,report.png,force_depth_<needle>.csv,...}\n", sc.value, a.report.c_str());
  }
  if (loop.faulted()) {
    spdlog::error("error: simulation fault, the physics stopped at {}", loop.fault_text());
    SavedState st;
    if (!a.save_on_fault.empty() && loop.last_good_state(st)) save_fault_state(a.save_on_fault, st, scene);
    else if (a.save_on_fault.empty()) spdlog::error("(--save-on-fault FILE keeps the last good state)");
    return kExitFault;
  }
  return rc;
}

void add_run_command(CLI::App& app, Runner& run) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* sub = app.add_subcommand("run", "run a scenario live on the real-time physics thread (window, or headless)");
  sub->add_option("scenario", a->scenario, "scenario YAML file")->required()->check(CLI::ExistingFile);
  sub->add_option("--script", a->script, "scripted device: YAML timeline (config/scripts/*.yaml)")->check(CLI::ExistingFile);
  sub->add_option("--record", a->record, "record every applied command with its tick to FILE");
  sub->add_flag("--headless", a->headless, "no window even when one is available");
  sub->add_option("--device", a->device,
                  "what drives the needle without a script: auto (SpaceMouse if spacenavd runs, else mouse+keyboard), spacemouse, mouse, none")
      ->check(CLI::IsMember({"auto", "spacemouse", "mouse", "none"}))
      ->capture_default_str();
  sub->add_option("--duration", a->duration, "simulated time [s] (headless default: the script's, else the scenario's)")
      ->check(simulated_seconds());
  sub->add_option("--factor", a->factor, "slow motion: simulated seconds per wall second (default 1 = real time)")
      ->check(in_range(1e-3, 100.0, ""));
  sub->add_flag("--unpaced", a->unpaced, "do not keep real time: tick as fast as possible");
  sub->add_flag("--hash", a->hash_only, "print only the final state hash (16 hex digits)");
  sub->add_option("--probe-device", a->probe_device, "what moves the probe live: none, spacemouse (six axes), mouse (keyboard bindings)")
      ->check(CLI::IsMember({"none", "spacemouse", "mouse"}))
      ->capture_default_str();
  sub->add_option("--save-on-fault", a->save_on_fault, "when the physics faults, write the last good state to FILE (atomically)");
  sub->add_flag("--no-watchdog", a->no_watchdog, "do not check energy growth, volume drift and particles leaving the scene each tick");
  sub->add_option("--state", a->state, "go on from a saved state (--save-on-fault, the window's Save state) of this scenario")
      ->check(CLI::ExistingFile);
  // test hook: a NaN injected into particle 0 before tick N (nan@N) or an exception (throw@N)
  sub->add_option("--inject-fault", a->inject, "")->group("");
  sub->add_option("--report", a->report, "session report folder: metrics.json (score), report.png, force-depth CSVs");
  sub->add_option("--trainee", a->trainee, "trainee name recorded in metrics.json");
  sub->add_option("--session", a->session, "session name in metrics.json (default: the report folder's name)");
#if PROSTATESIM_IGTL
  sub->add_option("--igtl-port", a->igtl_port,
                  "serve poses and TRUS images over OpenIGTLink on this TCP port (18944 is usual; 0: any free port), "
                  "take tracked ProbeTo*/NeedleTo* transforms in (docs/igtl.md)")
      ->check(CLI::Range(0, 65535));
#endif
  sub->callback([a, &run] { run = [a] { return run_live(*a); }; });
}

}  // namespace ps::app
