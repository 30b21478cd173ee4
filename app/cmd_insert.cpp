// `prostatesim insert SCENARIO [--duration S] --out DIR`: runs a scenario with its `needles:`
// section headless and writes, per needle, force_depth_<name>.csv (one row per tick), and
// needle_events.csv, seeds.csv (planned vs actual), cores.csv (biopsy notch contents), and the
// session's training metrics and score, metrics.json (engine/metrics, docs/metrics.md), with the
// one-page report.png (app/session_report.h).
// Parses, compiles and builds the needles first: bad input exits 2 before anything is written.
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "app/session_report.h"
#include "engine/io/png_write.h"
#include "engine/metrics/metrics_json.h"
#include "engine/metrics/metrics_options.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/needle_output.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

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
  sub->add_option("--duration", args->duration, "simulated time [s] (default: the scenario's)")->check(CLI::PositiveNumber);
  sub->add_option("--out", args->out, "output folder (created)")->capture_default_str();
  sub->add_option("--trainee", args->trainee, "trainee name recorded in metrics.json");
  sub->add_option("--session", args->session, "session name recorded in metrics.json (default: the output folder's name)");
  sub->callback([args, &run] {
    run = [args]() -> int {
      const ScenarioSpec spec = parse_scenario_file(args->scenario);
      auto model = compile_scenario(spec);
      auto tool = make_needle_tool(model, spec.needles);
      if (!tool) throw InputError(spec.file, 0, "needles", "the scenario has no needles: section");
      NeedleTool& needles = *tool;
      SessionMetrics metrics(*model, needles, metrics_options_for(spec));
      for (const auto& w : model->compile_warnings) spdlog::warn("warning: {}", w);
      for (const auto& w : needles.warnings()) spdlog::warn("warning: {}", w);
      Simulation sim(model);
      sim.add_tool(std::move(tool));
      ForceDepthRecorder rec(needles.count());
      const double duration = args->duration > 0 ? args->duration : model->duration;
      const long ticks = std::lround(duration / model->dt);
      bool ok = true;
      for (long i = 0; i < ticks && ok; ++i) {
        ok = sim.tick();
        rec.sample(needles, sim.state().time);
        metrics.observe(needles, sim.state());
      }
      std::filesystem::create_directories(args->out);
      const std::string dir = args->out + "/";
      for (int i = 0; i < needles.count(); ++i) write_force_depth_csv(dir + "force_depth_" + needles.spec(i).name + ".csv", rec.samples(i));
      write_file_atomic(dir + "needle_events.csv", needle_events_csv(needles, *model));
      write_file_atomic(dir + "seeds.csv", seeds_csv(needles));
      write_file_atomic(dir + "cores.csv", cores_csv(needles));
      const SessionReport report = metrics.finish(needles, sim.state(), !ok);
      const Score score = score_session(report);
      const std::string session = !args->session.empty() ? args->session : std::filesystem::path(args->out).lexically_normal().filename().string();
      write_file_atomic(dir + "metrics.json", metrics_json(report, score, {args->trainee, session}));
      const RgbImage page = render_session_report(*model, sim.state(), needles, rec, report, score);
      write_png_atomic(dir + "report.png", page.width, page.height, 3, page.pixels.data());
      for (int i = 0; i < needles.count(); ++i) {
        const ForceDepthMetrics m = force_depth_metrics(rec.samples(i), 0.0, 1.0);
        std::printf("%s: peak %.3f N at %.2f mm, final %.3f N at %.2f mm\n", needles.spec(i).name.c_str(), m.peak_force,
                    1e3 * m.peak_depth, m.end_force, 1e3 * m.end_depth);
      }
      for (const auto& e : needles.events().snapshot())
        if (e.kind == NeedleEventKind::Puncture || e.kind == NeedleEventKind::BoneHit || e.kind == NeedleEventKind::Core ||
            e.kind == NeedleEventKind::ForceClamped)
          std::printf("  t=%.4f s %s %s %s depth %.2f mm force %.3f N\n", e.time, needles.spec(e.needle).name.c_str(),
                      needle_event_name(e.kind), e.component >= 0 ? model->components[e.component].name.c_str() : "-",
                      1e3 * e.depth, e.force);
      const NeedleCouplingStats& cs = needles.coupling();
      std::printf("needle-tissue coupling: largest stability bound G h^2 %.3g (budget %.3g), springs softened in %lld substeps\n",
                  cs.bound_max, kCouplingBudget, static_cast<long long>(cs.softened_substeps));
      std::printf("score %.1f / 100; targeting %s\n", score.value, han_scale_text(report.mean_error).c_str());
      std::printf("wrote %s{force_depth_<needle>.csv,needle_events.csv,seeds.csv,cores.csv,metrics.json,report.png}\n", dir.c_str());
      if (!ok) {
        spdlog::error("error: simulation stopped: {}", sim.state().fault.describe(*model));
        return kExitFault;
      }
      return kExitOk;
    };
  });
}

}  // namespace ps::app
