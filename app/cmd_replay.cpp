// `prostatesim replay SCENARIO --recording FILE [--hash] [--duration S]` and, with a registered
// frame writer, its frame options (--out DIR ...: PNG frames, render/).
// Replays a recording headless in lock-step (engine/realtime/lockstep.h: no thread, no wall
// clock, as fast as it can) and prints the final state hash: the same 16 hex digits as the live
// run that recorded it, at any speed, with frames or without. A recording made on another
// scenario file, another program version or a malformed one exits 2 naming file:line.
// `--script F` replays a script instead of a recording (same lock-step path).
// The recording's periodic state hashes (`h` lines) are checked as the replay passes them; the
// first that differs is named (file:line, tick) and the exit code is 3. A simulation fault stops
// the replay, not the program: it is printed with tick, time and particle, --save-on-fault FILE
// writes the last good state, exit 3.
// `--report DIR [--trainee T] [--session S]`: the session report at the end (metrics.json with
// its score, report.png, force-depth and event CSVs; app/session/session_capture.h), fed after every
// tick, outside the step.
// `--state FILE`: start from a saved state of this scenario (engine/realtime/state_file.h) at its
// tick, the recording's or script's commands before it skipped; bad or foreign file: exit 2.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "engine/sim/watchdog.h"

#include "app/cli_ranges.h"
#include "app/commands.h"
#include "app/output_paths.h"
#include "app/core/run_session.h"
#include "app/session/session_capture.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {

struct ReplayArgs {
  std::string scenario, recording, script, save_on_fault, inject, state;
  std::string report, trainee, session;
  bool hash_only = false, no_watchdog = false;
  double duration = -1.0;
};

int replay(const ReplayArgs& a) {
  Scene scene = load_scene(a.scenario);
  const Model& m = *scene.model;
  std::vector<Command> cmds;
  int64_t end_tick = -1;
  Recording rec;
  if (!a.recording.empty()) {
    rec = parse_recording_file(a.recording);
    check_recording_matches(rec, RecordingHeader{scene.spec.name, scene.content_hash, m.dt, m.substeps});
    cmds = rec.commands;
    if (rec.complete) end_tick = rec.fault_tick >= 0 ? rec.fault_tick + 1 : rec.end_tick;  // a faulted run: to its fault
    else {  // cut short (a crash): to its last command or hash
      end_tick = std::max(cmds.empty() ? int64_t{0} : cmds.back().tick + 1, rec.hashes.empty() ? int64_t{0} : rec.hashes.back().tick);
      spdlog::warn("warning: {} has no end line (the run did not finish): replaying to its last command, tick {}", a.recording, end_tick);
    }
  } else {
    const Script s = parse_script_file(a.script);
    cmds = script_commands(s, scene);
    const double d = s.duration > 0 ? s.duration : m.duration;
    end_tick = static_cast<int64_t>(std::llround(d / m.dt));
  }
  if (a.duration > 0) end_tick = static_cast<int64_t>(std::llround(a.duration / m.dt));
  const FaultInjection inject = parse_fault_injection(a.inject);
  SavedState start_state;
  if (!a.state.empty()) {
    if (!a.report.empty()) throw InputError(a.state, 0, "--state", "--report covers a session from the scenario's start; not with --state");
    start_state = read_state_file(a.state);
    check_state_matches(start_state, scene.spec.name, scene.content_hash);
  }
  std::unique_ptr<SessionCapture> capture;
  if (!a.report.empty()) {
    capture = SessionCapture::make(scene);
    if (!capture) throw InputError(a.scenario, 0, "--report", "the scenario has no needles: section (nothing to score)");
    prepare_output_dir(a.report, "--report");
  }
  CommandPlayer player(std::move(cmds));
  LockstepRunner runner(*scene.sim);
  runner.add_source(&player);
  if (capture) runner.add_source(capture.get());
  HashVerifier verifier(rec);
  if (!a.recording.empty() && rec.header.hash_every > 0) runner.runner().set_hash_observer(&verifier, rec.header.hash_every);
  const Watchdog watchdog(m);
  if (!a.no_watchdog) runner.runner().set_watchdog(&watchdog);
  runner.runner().keep_last_good(true);
  if (inject.tick >= 0) runner.runner().inject_fault(inject.tick, 0, inject.internal);
  if (!a.state.empty()) {
    runner.runner().load_state(start_state);  // the player skips to the state's tick
    if (!a.hash_only)
      std::printf("loaded %s: tick %lld, t=%.4g s, state hash %s\n", a.state.c_str(), static_cast<long long>(start_state.tick),
                  start_state.time, hex16(start_state.state_hash).c_str());
  }
  int rc = kExitOk;
  if (replay_frames().run && replay_frames().wanted && replay_frames().wanted()) {
    ReplaySession session{scene, runner, end_tick, a.scenario};
    rc = replay_frames().run(session);
  }
  runner.advance_to(end_tick);
  const uint64_t h = runner.hash();
  const auto& rr = runner.applier().refusals();
  for (int i = 0; i < rr.size(); ++i) spdlog::warn("{}", rr.at(i).describe());
  if (!a.hash_only)  // commands the tools adjusted to their limits (--hash prints the hash alone)
    for (const std::string& l : scene_tool_reports(scene)) spdlog::warn("{}", l);
  if (a.hash_only) {
    std::printf("%s\n", hex16(h).c_str());
  } else {
    std::printf("%s: replayed %lld ticks (%.4g s), %lld commands applied, %lld refused\n", scene.spec.name.c_str(),
                static_cast<long long>(runner.tick()), scene.sim->state().time, static_cast<long long>(runner.applier().applied()),
                static_cast<long long>(runner.applier().refused()));
    std::printf("state hash %s\n", hex16(h).c_str());
  }
  if (verifier.diverged()) {
    spdlog::error("error: replay diverged: {}", verifier.describe());
    return kExitFault;
  }
  if (rec.fault_tick >= 0 && !runner.faulted() && runner.tick() > rec.fault_tick) {
    spdlog::error("error: replay diverged: {}: the live run faulted at tick {}, the replay ran it without a fault", a.recording,
                  rec.fault_tick);
    return kExitFault;
  }
  if (rec.complete && rec.fault_tick < 0 && !runner.faulted() && runner.tick() == rec.end_tick && h != rec.end_hash) {
    spdlog::error("error: replay diverged: {}:{}: state hash {} at tick {}, the live run recorded {}", a.recording, rec.end_line, hex16(h),
                  runner.tick(), hex16(rec.end_hash));
    return kExitFault;
  }
  if (capture) {
    const Score sc = capture->write(a.report, runner.faulted(), a.trainee, a.session);
    if (!a.hash_only) std::printf("score %.1f / 100; wrote %s/{metrics.json,report.png,force_depth_<needle>.csv,...}\n", sc.value, a.report.c_str());
  }
  if (runner.faulted()) {
    spdlog::error("error: simulation fault, the replay stopped at {}", runner.runner().fault_text());
    if (rec.fault_tick == runner.tick()) spdlog::error("(the live run faulted at the same tick: the fault replays)");
    else if (rec.fault_tick >= 0) spdlog::error("(the live run faulted at tick {})", rec.fault_tick);
    SavedState st;
    if (!a.save_on_fault.empty() && runner.runner().last_good(st)) save_fault_state(a.save_on_fault, st, scene);
    return kExitFault;
  }
  if (!a.hash_only && verifier.checked() > 0) std::printf("%d recorded state hashes checked: all equal\n", verifier.checked());
  return rc;
}
}  // namespace

void add_replay_command(CLI::App& app, Runner& run) {
  auto a = std::make_shared<ReplayArgs>();
  CLI::App* sub = app.add_subcommand("replay", "replay a recording (or a script) headless, bit for bit, and print the state hash");
  sub->add_option("scenario", a->scenario, "scenario YAML file")->required()->check(CLI::ExistingFile);
  auto* r = sub->add_option("--recording", a->recording, "recording made by `run --record`")->check(CLI::ExistingFile);
  auto* s = sub->add_option("--script", a->script, "a script instead of a recording")->check(CLI::ExistingFile);
  r->excludes(s);
  sub->add_flag("--hash", a->hash_only, "print only the final state hash (16 hex digits)");
  sub->add_option("--duration", a->duration, "stop after this simulated time [s] (default: where the recording ends)")
      ->check(simulated_seconds());
  sub->add_option("--save-on-fault", a->save_on_fault, "when the physics faults, write the last good state to FILE (atomically)");
  sub->add_flag("--no-watchdog", a->no_watchdog, "do not check energy growth, volume drift and particles leaving the scene each tick");
  sub->add_option("--state", a->state, "start from a saved state (--save-on-fault, the window's Save state) of this scenario")
      ->check(CLI::ExistingFile);
  sub->add_option("--inject-fault", a->inject, "")->group("");  // test hook: nan@TICK or throw@TICK
  sub->add_option("--report", a->report, "session report folder: metrics.json (score), report.png, force-depth CSVs");
  sub->add_option("--trainee", a->trainee, "trainee name recorded in metrics.json");
  sub->add_option("--session", a->session, "session name in metrics.json (default: the report folder's name)");
  if (replay_frames().add_options) replay_frames().add_options(*sub);
  sub->callback([a, sub, &run] {
    if (a->recording.empty() && a->script.empty()) throw CLI::ValidationError("replay", "one of --recording or --script is required");
    run = [a] { return replay(*a); };
  });
}

}  // namespace ps::app
