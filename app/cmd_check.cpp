// `prostatesim check SCENARIO`: validates a scenario and prints per-component particle and
// triplet counts, the model hash, memory use and the largest stable time step.
#include <cstdio>
#include <ctime>

#include "app/commands.h"
#include "engine/scenario/model_hash.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"

namespace ps::app {

void add_check_command(CLI::App& app, Runner& run) {
  auto scenario = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand("check", "validate a scenario; print particle/triplet counts, memory and stable dt");
  sub->add_option("scenario", *scenario, "scenario YAML file")->required();
  sub->callback([scenario, &run] {
    run = [scenario]() -> int {
      CompileReport rep;
      // CPU time too: on a shared machine the wall time measures the other processes as well
      const std::clock_t cpu0 = std::clock();
      auto model = compile_scenario(parse_scenario_file(*scenario), &rep);
      const double cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
      const Model& m = *model;
      std::printf("%s: ok (compiled in %.3f s, %.3f s CPU)\n", m.name.c_str(), rep.seconds, cpu_s);
      // The compiled model's fingerprint (engine/scenario/model_hash.h): equal hashes mean the same
      // particles, neighbourhoods, weights and constraints, which scripts/model_hashes.sh uses to
      // show that a refactoring of compile_scenario changed nothing.
      std::printf("model hash %016llx\n", static_cast<unsigned long long>(model_hash(m)));
      std::printf("%-14s %-8s %9s %10s %10s %10s\n", "component", "kind", "particles", "neighbours", "triplets", "beta_trip");
      for (const Component& c : m.components) {
        long nb = 0, tr = 0, bt = 0;
        for (int p = c.first_particle; p < c.first_particle + c.particle_count; ++p) {
          nb += m.nbr_start[p + 1] - m.nbr_start[p];
          tr += m.triplet_count[p];
          bt += m.beta_start[p + 1] - m.beta_start[p];
        }
        const char* kind = c.kind == ComponentKind::Rigid ? "rigid" : c.kind == ComponentKind::Active ? "active" : "elastic";
        std::printf("%-14s %-8s %9d %10ld %10ld %10ld\n", c.name.c_str(), kind, c.particle_count, nb, tr, bt);
      }
      const double bytes = m.particle_count() * (3 * 24.0 + 6 * 8.0) + m.nbr.size() * 12.0 + m.beta.size() * sizeof(BetaTriplet) +
                           m.particle_count() * (5 * 24.0);  // model arrays + state arrays
      std::printf("total particles %d, model+state memory %.2f MiB\n", m.particle_count(), bytes / (1024.0 * 1024.0));
      std::printf("largest stable substep %.4g s (linearisation at rest); using %d substep(s) of %.4g s per %.4g s tick\n",
                  m.stable_dt_estimate, m.substeps, m.dt / m.substeps, m.dt);
      for (const auto& w : rep.warnings) std::printf("warning: %s\n", w.c_str());
      for (const auto& w : rep.notes) std::printf("note: %s\n", w.c_str());
      return kExitOk;
    };
  });
}

}  // namespace ps::app
