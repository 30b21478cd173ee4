// `prostatesim simulate SCENARIO [--duration S | --until-rest] --out DIR`
// Parses and compiles first: bad input exits 2 before anything is written to DIR.
// Writes particles.csv, summary.json, one OBJ per component surface and displacement.csv (every
// particle's displacement from the start of the run, engine/tools/probe/displacement_field.h: colour
// by u_mm), and prints the prostate's displacement (mean, max, per zone along +z) when the scene
// has a component named prostate.
#include <spdlog/spdlog.h>


#include "app/cli_ranges.h"
#include "app/commands.h"
#include "app/output_paths.h"
#include "engine/io/output.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"
#include "engine/tools/probe/displacement_field.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"

namespace ps::app {

namespace {
struct SimulateArgs {
  std::string scenario;
  std::string out = "out/simulate";
  double duration = -1.0;
  bool until_rest = false;
};
}  // namespace

void add_simulate_command(CLI::App& app, Runner& run) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub = app.add_subcommand("simulate", "run a scenario headless and write particles.csv, summary.json, OBJ surfaces");
  sub->add_option("scenario", args->scenario, "scenario YAML file")->required();
  auto* dur = sub->add_option("--duration", args->duration, "simulated time [s] (default: the scenario's; cap with --until-rest)");
  sub->add_flag("--until-rest", args->until_rest,
                "stop when kinetic energy stays below the scenario's rest.kinetic_energy_j (default 1e-7 J) for rest.hold_s (default 0.05 s)");
  sub->add_option("--out", args->out, "output folder (created)")->capture_default_str();
  dur->check(simulated_seconds());
  sub->callback([args, &run] {
    run = [args]() -> int {
      const ScenarioSpec spec = parse_scenario_file(args->scenario);
      // the model and the instruments of the scene (each only when its section is present)
      Scene scene = build_scene(spec);
      const CompileReport& rep = scene.report;
      const std::shared_ptr<const Model> model = scene.model;
      Simulation& sim = *scene.sim;
      auto* probe = scene.tools.as<ProbeTool>();
      auto* filling = scene.tools.as<FillingTool>();
      RunOptions opt;
      opt.duration = args->duration > 0 ? args->duration : (args->until_rest ? std::max(60.0, model->duration) : model->duration);
      opt.until_rest = args->until_rest;
      opt.rest_energy = spec.rest_kinetic_energy;
      opt.rest_hold = spec.rest_hold;
      spdlog::info("{}: {} particles, {} substeps of {:.3g} s per tick, compiled in {:.3f} s", spec.name,
                   model->particle_count(), model->substeps, model->dt / model->substeps, rep.seconds);
      // after compiling (bad input writes nothing) and before the run (which must not end in a failed write)
      prepare_output_dir(args->out, "--out");
      const std::vector<Vec3> start = sim.state().x;  // displacements are from here
      const RunResult r = run_simulation(sim, opt);
      const std::string dir = args->out + "/";
      write_summary_json(dir + "summary.json", *model, r);
      if (r.faulted) {
        spdlog::error("error: simulation stopped: {} (summary: {}summary.json; no particle file written)", r.fault, dir);
        return kExitFault;
      }
      write_particles_csv(dir + "particles.csv", *model, sim.state());
      for (size_t c = 0; c < model->components.size(); ++c)
        write_surface_obj(dir + model->components[c].name + ".obj", component_surface_mesh(*model, sim.state(), static_cast<int>(c)));
      write_displacement_csv(dir + "displacement.csv", *model, -1, start, sim.state().x, Vec3::UnitZ());
      std::printf("%s: %lld steps, %.4g s simulated in %.3g s wall; kinetic energy %.3g J, max speed %.3g m/s\n",
                  spec.name.c_str(), static_cast<long long>(r.steps), r.sim_time, r.wall_time, r.kinetic_energy, r.max_speed);
      for (const auto& [c, e] : r.volume_error) std::printf("  volume error %-12s %.3g\n", c.c_str(), e);
      for (const auto& w : r.warnings) std::printf("  warning: %s\n", w.c_str());
      if (const int pc = model->find_role(Role::Prostate); pc >= 0) {
        const DisplacementStats d = displacement_stats(*model, pc, start, sim.state().x, Vec3::UnitZ());
        std::printf("  prostate displacement: mean %.3f mm, max %.3f mm; mean per zone: base %.3f, mid %.3f, apex %.3f mm\n",
                    d.all.mean * 1e3, d.all.max * 1e3, d.base.mean * 1e3, d.mid.mean * 1e3, d.apex.mean * 1e3);
      }
      if (probe) for (const auto& w : probe->reports()) std::printf("  probe: %s\n", w.c_str());
      if (filling) for (const auto& w : filling->reports()) std::printf("  filling: %s\n", w.c_str());
      std::printf("wrote %s{particles.csv,displacement.csv,summary.json,<component>.obj}\n", dir.c_str());
      return kExitOk;
    };
  });
}

}  // namespace ps::app
