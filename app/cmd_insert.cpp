// `prostatesim insert SCENARIO [--duration S] --out DIR`: runs a scenario with its `needles:`
// section headless and writes, per needle, force_depth_<name>.csv (one row per tick), and
// needle_events.csv, seeds.csv (planned vs actual), cores.csv (biopsy notch contents), and the
// session's training metrics and score, metrics.json (engine/metrics, docs/metrics.md), with the
// one-page report.png (app/session/session_report.h): the very session report of `run --report` and
// `replay --report` (app/session/session_capture.h: same capture, same writer, same format), of a scene
// made of the needles alone (insert simulates no probe and no filling).
// Parses, compiles and builds the needles first: bad input exits 2 before anything is written.
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>

#include "app/cli_ranges.h"
#include "app/commands.h"
#include "app/output_paths.h"
#include "app/session/session_capture.h"
#include "engine/metrics/metrics_json.h"
#include "engine/realtime/lockstep.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"
#include "engine/tools/needle/needle_output.h"
#include "engine/util/error.h"
#include "engine/tools/needle/needle.h"

namespace ps::app {

namespace {
struct InsertArgs {
  std::string scenario;
  std::string out = "out/insert";
  double duration = -1.0;
  std::string trainee, session;
};
}  // namespace

void add_insert_command(CLI::App& app, Runner& run) {
  auto args = std::make_shared<InsertArgs>();
  CLI::App* sub = app.add_subcommand("insert", "run a scenario's needles headless; write force-vs-depth, events, seeds, cores CSV");
  sub->add_option("scenario", args->scenario, "scenario YAML file with a needles: section")->required();
  sub->add_option("--duration", args->duration, "simulated time [s] (default: the scenario's)")->check(simulated_seconds());
  sub->add_option("--out", args->out, "output folder (created)")->capture_default_str();
  sub->add_option("--trainee", args->trainee, "trainee name recorded in metrics.json");
  sub->add_option("--session", args->session, "session name recorded in metrics.json (default: the output folder's name)");
  sub->callback([args, &run] {
    run = [args]() -> int {
      // A scene of the needles alone (insert runs no probe and no filling, as it always has), fed
      // through the same lock-step runner and session capture as `run --report` and
      // `replay --report`, so insert writes the same session report: metrics.json with its score,
      // report.png (3D view, force-depth plots, numbers) and the CSVs.
      Scene scene;
      scene.spec = parse_scenario_file(args->scenario);
      scene.model = compile_scenario(scene.spec);
      auto tool = make_needle_tool(scene.model, scene.spec.needles);
      if (!tool) throw InputError(scene.spec.file, 0, "needles", "the scenario has no needles: section");
      const NeedleTool& needles = *tool;
      for (const auto& w : scene.model->compile_warnings) spdlog::warn("warning: {}", w);
      for (const auto& w : needles.warnings()) spdlog::warn("warning: {}", w);
      scene.sim = std::make_unique<Simulation>(scene.model);
      scene.sim->add_tool(std::move(tool));
      scene.tools.sim = scene.sim.get();
      scene.tools.entries.push_back({&NeedleTool::kind(), 0});
      const Model& model = *scene.model;
      auto capture = SessionCapture::make(scene);  // throws on a target outside the scene: before anything is written
      prepare_output_dir(args->out, "--out");
      const double duration = args->duration > 0 ? args->duration : model.duration;
      const int64_t ticks = std::llround(duration / model.dt);
      LockstepRunner runner(*scene.sim);
      runner.add_source(capture.get());
      const bool ok = runner.advance_to(ticks);
      const Score score = capture->write(args->out, !ok, args->trainee, args->session);
      const SessionReport report = capture->report(!ok);
      const std::string dir = args->out + "/";
      const ForceDepthRecorder& rec = capture->force_depth();
      for (int i = 0; i < needles.count(); ++i) {
        const ForceDepthMetrics m = force_depth_metrics(rec.samples(i), 0.0, 1.0);
        std::printf("%s: peak %.3f N at %.2f mm, final %.3f N at %.2f mm\n", needles.spec(i).name.c_str(), m.peak_force,
                    1e3 * m.peak_depth, m.end_force, 1e3 * m.end_depth);
      }
      for (const auto& e : needles.events().snapshot())
        if (e.kind == NeedleEventKind::Puncture || e.kind == NeedleEventKind::BoneHit || e.kind == NeedleEventKind::Core ||
            e.kind == NeedleEventKind::ForceClamped)
          std::printf("  t=%.4f s %s %s %s depth %.2f mm force %.3f N\n", e.time, needles.spec(e.needle).name.c_str(),
                      needle_event_name(e.kind), e.component >= 0 ? model.components[e.component].name.c_str() : "-",
                      1e3 * e.depth, e.force);
      const NeedleCouplingStats& cs = needles.coupling();
      std::printf("needle-tissue coupling: largest stability bound G h^2 %.3g (budget %.3g), springs softened in %lld substeps\n",
                  cs.bound_max, kCouplingBudget, static_cast<long long>(cs.softened_substeps));
      std::printf("score %.1f / 100; targeting %s\n", score.value, han_scale_text(report.mean_error).c_str());
      std::printf("wrote %s{force_depth_<needle>.csv,needle_events.csv,seeds.csv,cores.csv,metrics.json,report.png}\n", dir.c_str());
      if (!ok) {
        spdlog::error("error: simulation stopped: {}", runner.runner().fault_text());
        return kExitFault;
      }
      return kExitOk;
    };
  });
}

}  // namespace ps::app
