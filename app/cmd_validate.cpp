// `prostatesim validate [CASE...] [--json FILE]`: runs validation cases, prints a table
// (case, metric, value, reference, unit) and exits 0 when every row is within its tolerance,
// 1 otherwise. --json writes the same rows as an array of objects with exactly those five keys.
// --out DIR: where cases write per-particle files (the probe and filling cases'
// <case>_displacement.csv); default out/validate.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/cli_ranges.h"
#include "app/commands.h"
#include "app/output_paths.h"
#include "app/progress.h"
#include "app/checks/validate_indentation.h"
#include "app/checks/validate_probe.h"
#include "app/checks/validation.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {

struct ValidateArgs {
  std::vector<std::string> cases;
  std::string json;
  std::string root;   // repository root (config/validation inside)
  std::string data;   // ../shared/data
  std::string out = "out/validate";  // per-particle files of the cases
  std::string model;  // indentation cases: run this tissue model instead of the scenario's
  std::vector<double> spacings;  // indentation cases: particle spacings [mm]
};

std::string find_root(const std::string& given) {
  if (!given.empty()) return given;
  namespace fs = std::filesystem;
  for (fs::path p = fs::current_path(); !p.empty(); p = p.parent_path()) {
    if (fs::exists(p / "config/validation")) return p.string();
    if (p == p.parent_path()) break;
  }
  return ".";
}

}  // namespace

void add_validate_command(CLI::App& app, Runner& run) {
  auto args = std::make_shared<ValidateArgs>();
  CLI::App* sub = app.add_subcommand("validate", "compare the simulator with reference data; exit 1 if out of tolerance");
  sub->add_option("cases", args->cases, "cases to run (default: all): truth_cylinder cube_frictionless cube_bonded convergence ...");
  sub->add_option("--json", args->json, "also write the rows as a JSON array to this file");
  sub->add_option("--root", args->root, "repository root holding config/validation (default: found from the working directory)");
  sub->add_option("--data", args->data, "reference data folder (default: ROOT/../shared/data)");
  sub->add_option("--out", args->out, "folder for per-particle files (probe/filling cases: <case>_displacement.csv)")
      ->capture_default_str();
  sub->add_option("--model", args->model, "punch_halfspace, sphere_indentation: run this tissue model (paper, strain, tet) instead of the scenario's")
      ->check(CLI::IsMember({"paper", "strain", "tet"}));
  sub->add_option("--spacings-mm", args->spacings, "punch_halfspace, sphere_indentation: particle spacings to run, multiples of 5 (default 10 5)")
      ->check(in_range(0.0, 1000.0, "mm", true));
  sub->callback([args, &run] {
    run = [args]() -> int {
      const std::string root = find_root(args->root);
      const std::string data = args->data.empty() ? root + "/../shared/data" : args->data;
      prepare_output_file(args->json, "--json");
      set_displacement_output_dir(args->out);
      set_indentation_model(args->model);
      for (double h : args->spacings)
        if (std::abs(h / 5.0 - std::round(h / 5.0)) > 1e-9)
          throw InputError("", 0, "validate --spacings-mm", "spacing " + std::to_string(h) + " mm is not a multiple of 5 mm (the FEM field's grid)");
      set_indentation_spacings(args->spacings);
      std::vector<const ValidationCase*> chosen;
      for (const std::string& name : args->cases) {
        const ValidationCase* found = nullptr;
        for (const auto& c : validation_cases()) if (c.name == name) found = &c;
        if (!found) {
          std::string all;
          for (const auto& c : validation_cases()) all += " " + c.name;
          throw InputError("", 0, "validate", "unknown case '" + name + "' (known:" + all + ")");
        }
        chosen.push_back(found);
      }
      if (chosen.empty()) for (const auto& c : validation_cases()) chosen.push_back(&c);
      for (const ValidationCase* c : chosen)
        if (c->writes_files) {
          prepare_output_dir(args->out, "--out");
          break;
        }
      std::vector<ValidationRow> rows;
      bool all_pass = true;
      std::printf("%-18s %-40s %12s %12s %-5s %s\n", "case", "metric", "value", "reference", "unit", "status");
      Progress progress("validate", static_cast<int>(chosen.size()));
      int progress_done = 0;
      for (const ValidationCase* c : chosen) {
        progress.update(progress_done++, c->name);
        std::vector<ValidationRow> got;
        try {
          got = c->run(root, data);
        } catch (const InputError&) {
          throw;
        } catch (const std::exception& e) {
          got.push_back({c->name, "error", std::nan(""), 0.0, "", 0.0});
          std::printf("%-18s failed to run: %s\n", c->name.c_str(), e.what());
        }
        progress.clear();
        for (const auto& r : got) {
          const bool ok = r.pass();
          all_pass &= ok;
          char ref[32] = "-";
          if (!std::isnan(r.reference)) std::snprintf(ref, sizeof ref, "%.4g", r.reference);
          char tol[40] = "";
          if (!std::isnan(r.reference)) std::snprintf(tol, sizeof tol, " (tol %.3g)", r.tolerance);
          std::printf("%-18s %-40s %12.4g %12s %-5s %s%s\n", r.case_name.c_str(), r.metric.c_str(), r.value, ref,
                      r.unit.c_str(), ok ? "ok" : "OUT", tol);
          std::fflush(stdout);
          rows.push_back(r);
        }
        progress.step(c->name);
      }
      if (!args->json.empty()) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& r : rows) {
          nlohmann::json o;
          o["case"] = r.case_name;
          o["metric"] = r.metric;
          o["value"] = std::isfinite(r.value) ? nlohmann::json(r.value) : nlohmann::json();
          o["reference"] = std::isnan(r.reference) ? nlohmann::json() : nlohmann::json(r.reference);
          o["unit"] = r.unit;
          j.push_back(o);
        }
        write_file_atomic(args->json, j.dump(2) + "\n");
      }
      std::printf("%s\n", all_pass ? "all within tolerance" : "SOME OUT OF TOLERANCE");
      return all_pass ? kExitOk : kExitOutOfTolerance;
    };
  });
}

}  // namespace ps::app
