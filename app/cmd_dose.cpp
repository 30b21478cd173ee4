// `prostatesim dose` and `prostatesim plan` (issue 46, docs/dosimetry.md).
//   dose --isotope I125_6711 --seeds SEEDS.csv --points POINTS.csv --out DOSE.csv
//     TG-43U1 total dose of a permanent implant at each point (engine/dosimetry); DOSE.csv repeats
//     the points with dose_gy.
//   plan SCENARIO --prescription-gy 145 --out PLAN.yaml [--isotope I125_6711] [--strength-u 0.5]
//     seed positions on the scenario's template lines from the prostate's rest shape
//     (engine/dosimetry/plan.h: simulated annealing over the candidates' dose matrix); exit 1 naming
//     each constraint the plan cannot meet, nothing written.
// Bad input (unknown isotope, a seed file with a missing column or a non-positive strength, an
// output path that cannot be written) exits 2 naming the file, line and field; nothing is written.
#include <cstdio>
#include <fstream>
#include <sstream>

#include "app/commands.h"
#include "app/output_paths.h"
#include "engine/dosimetry/dose_csv.h"
#include "engine/dosimetry/plan.h"
#include "engine/dosimetry/seed.h"
#include "engine/metrics/implant_dosimetry.h"
#include "engine/metrics/metrics_options.h"
#include "engine/sim/scene.h"
#include "engine/tools/probe/probe.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {

std::string read_text(const std::string& path, const std::string& option) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, option, "cannot read the file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

const dosimetry::SourceModel& isotope_or_throw(const std::string& name) {
  const dosimetry::SourceModel* s = dosimetry::find_source_model(name);
  if (!s) throw InputError("command line", 0, "--isotope", "unknown seed model '" + name + "' (known: " + dosimetry::source_model_names() + ")");
  return *s;
}

struct DoseArgs {
  std::string isotope = "I125_6711", seeds, points, out;
};

struct PlanArgs {
  std::string scenario, out, isotope = "I125_6711";
  double prescription_gy = 145.0, strength_u = 0.5;
};

}  // namespace

void add_dose_command(CLI::App& app, Runner& run) {
  auto a = std::make_shared<DoseArgs>();
  CLI::App* sub = app.add_subcommand("dose", "TG-43U1 total dose of a permanent seed implant at given points");
  sub->add_option("--isotope", a->isotope, "seed model: " + dosimetry::source_model_names())->capture_default_str();
  sub->add_option("--seeds", a->seeds, "seeds CSV: x_mm,y_mm,z_mm,axis_x,axis_y,axis_z,air_kerma_strength_U")->required();
  sub->add_option("--points", a->points, "points CSV: x_mm,y_mm,z_mm")->required();
  sub->add_option("--out", a->out, "output CSV: the points with dose_gy")->required();
  sub->callback([a, &run] {
    run = [a]() -> int {
      const dosimetry::SourceModel& s = isotope_or_throw(a->isotope);
      prepare_output_file(a->out, "--out");
      const auto seeds = dosimetry::parse_seeds_csv(read_text(a->seeds, "--seeds"), a->seeds);
      const auto points = dosimetry::parse_points_csv(read_text(a->points, "--points"), a->points);
      std::string out = "x_mm,y_mm,z_mm,dose_gy\n";
      char line[160];
      for (const Vec3& p : points) {
        std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g,%.6g\n", p.x(), p.y(), p.z(), dosimetry::total_dose_gy(s, seeds, p));
        out += line;
      }
      write_file_atomic(a->out, out);
      std::printf("%zu seeds (%s), %zu points: wrote %s\n", seeds.size(), s.name.c_str(), points.size(), a->out.c_str());
      return kExitOk;
    };
  });
}

void add_plan_command(CLI::App& app, Runner& run) {
  auto a = std::make_shared<PlanArgs>();
  CLI::App* sub = app.add_subcommand("plan", "pre-implant seed plan on the scenario's template (TG-43U1, simulated annealing)");
  sub->add_option("scenario", a->scenario, "scenario YAML with a prostate and a probe with a template")->required();
  sub->add_option("--prescription-gy", a->prescription_gy, "prescription dose [Gy]")->capture_default_str();
  sub->add_option("--isotope", a->isotope, "seed model: " + dosimetry::source_model_names())->capture_default_str();
  sub->add_option("--strength-u", a->strength_u, "air-kerma strength per seed [U]")->capture_default_str();
  sub->add_option("--out", a->out, "plan YAML to write")->required();
  sub->callback([a, &run] {
    run = [a]() -> int {
      isotope_or_throw(a->isotope);
      if (!(a->prescription_gy > 0.0)) throw InputError("command line", 0, "--prescription-gy", "must be positive");
      if (!(a->strength_u > 0.0)) throw InputError("command line", 0, "--strength-u", "must be positive");
      prepare_output_file(a->out, "--out");
      const Scene scene = load_scene(a->scenario);
      if (!scene.tools.has<ProbeTool>()) throw InputError(a->scenario, 0, "probe", "the scenario has no probe (the template rides on its stepper)");
      const auto& probe = *scene.tools.as<ProbeTool>();
      const MetricsOptions mo = metrics_options_for(scene.spec, *scene.model);
      DosimetryOptions opt;
      opt.isotope = a->isotope;
      opt.prescription_gy = a->prescription_gy;
      opt.strength_u = a->strength_u;
      opt.gland = mo.gland;
      dosimetry::PlanInput in;
      try {
        in = plan_input(*scene.model, probe, mo.urethra, opt);
      } catch (const InputError& e) {
        throw InputError(a->scenario, e.line(), e.field(), e.message());
      }
      const dosimetry::Plan p = dosimetry::optimise_plan(in);
      std::printf("plan for %s: %d seeds of %.3f U (%s) in %zu needles, prescription %.1f Gy (simulated annealing, %d round%s)\n",
                  scene.model->name.c_str(), p.seeds, a->strength_u, a->isotope.c_str(), p.needles.size(), a->prescription_gy, p.rounds,
                  p.rounds == 1 ? "" : "s");
      std::printf("prostate %.1f cc: D90 %.1f Gy, V100 %.1f %%, V150 %.1f %%, V200 %.1f %%; urethra D10 %.1f Gy, D30 %.1f Gy; "
                  "rectum D2cc %.1f Gy, V100 %.2f cc\n",
                  p.predicted.prostate_cc, p.predicted.prostate_d90_gy, 100 * p.predicted.prostate_v100, 100 * p.predicted.prostate_v150,
                  100 * p.predicted.prostate_v200, p.predicted.urethra_d10_gy, p.predicted.urethra_d30_gy, p.predicted.rectum_d2cc_gy,
                  p.predicted.rectum_v100_cc);
      for (const auto& c : p.checks)
        std::printf("  %-40s %8.1f %-2s (limit %.1f)  %s\n", c.name.c_str(), c.value, c.unit.c_str(), c.limit, c.pass ? "ok" : "NOT MET");
      if (!p.feasible()) {
        for (const auto& c : p.checks)
          if (!c.pass)
            std::fprintf(stderr, "error: %s: the plan cannot meet '%s' (%.1f %s against %.1f); nothing written\n", a->scenario.c_str(),
                         c.name.c_str(), c.value, c.unit.c_str(), c.limit);
        return kExitOutOfTolerance;
      }
      write_file_atomic(a->out, dosimetry::plan_yaml(p, in, scene.model->name));
      std::printf("wrote %s\n", a->out.c_str());
      return kExitOk;
    };
  });
}

}  // namespace ps::app
