// `prostatesim stress [SCENARIO...] [--quick] [--json FILE] [--csv FILE] [--cases A,B] [--soak S]
// [--script F|none]`: numerical robustness of each scene (app/checks/stress.h). Default: the default
// scenes and the validation scenes. Prints a table of what each case tried and what held; exit 0
// when everything held (or was refused cleanly), 3 when any case failed or ran out of its time
// budget. The one-hour soak benchmark of a default scene (its script looped, watchdog, drift
// figures, a progress line on stderr every --report-every seconds; a checkpoint every
// --checkpoint-every seconds, so a soak longer than a sitting goes on later with --resume):
//   prostatesim stress config/biopsy.yaml --cases soak --soak 3600 --budget 86400 --json soak.json
//       --checkpoint soak.ckpt            (later, the same command with --resume soak.ckpt added)
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "app/commands.h"
#include "app/output_paths.h"
#include "app/progress.h"
#include "app/checks/stress.h"
#include "engine/realtime/script.h"
#include "engine/realtime/soak_checkpoint.h"
#include "engine/sim/scene.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {

struct StressArgs {
  std::vector<std::string> scenarios;
  bool quick = false;
  std::string json, csv, root;
  double budget_s = -1, soak_s = -1, run_s = -1, report_every_s = 60;
  uint64_t seed = 1;
  std::vector<std::string> cases;
  std::string script;
  std::string checkpoint, resume;
  double checkpoint_every_s = 300;
};

std::vector<std::string> default_scenarios(const std::string& given_root) {
  namespace fs = std::filesystem;
  fs::path root = given_root;
  if (root.empty())
    for (fs::path p = fs::current_path(); !p.empty(); p = p.parent_path()) {
      if (fs::exists(p / "config/biopsy.yaml")) { root = p; break; }
      if (p == p.parent_path()) break;
    }
  if (root.empty() || !fs::exists(root / "config/biopsy.yaml"))
    throw InputError("", 0, "stress", "no scenario given and no config/biopsy.yaml found above the working directory (use --root)");
  std::vector<std::string> out;
  for (const char* s : {"biopsy.yaml", "brachytherapy.yaml", "bladder_filling.yaml"}) out.push_back((root / "config" / s).string());
  std::vector<std::string> val;
  for (const auto& e : fs::directory_iterator(root / "config/validation"))
    if (e.path().extension() == ".yaml") val.push_back(e.path().string());
  std::sort(val.begin(), val.end());
  out.insert(out.end(), val.begin(), val.end());
  return out;
}

std::string fmt_seconds(double t) {
  char b[64];
  std::snprintf(b, sizeof b, "t = %.6g s", t);
  return b;
}

std::string csv_field(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

void add_stress_command(CLI::App& app, Runner& run) {
  auto a = std::make_shared<StressArgs>();
  CLI::App* sub = app.add_subcommand("stress", "stress-test numerical stability of scenes; exit 3 if any case failed");
  sub->add_option("scenarios", a->scenarios, "scenario files (default: config/{biopsy,brachytherapy,bladder_filling}.yaml and config/validation/*.yaml)");
  sub->add_flag("--quick", a->quick, "short runs (CI size, under 3 minutes for the defaults)");
  sub->add_option("--json", a->json, "also write the table as JSON");
  sub->add_option("--csv", a->csv, "also write the table as CSV");
  sub->add_option("--root", a->root, "repository root holding config/ (default: found from the working directory)");
  sub->add_option("--budget", a->budget_s, "wall-clock budget per case [s] (default 60, quick 12)")->check(CLI::Range(0.1, 86400.0));
  sub->add_option("--soak", a->soak_s, "simulated time of the soak case [s] (default 0.5, quick 0.05; the benchmark by hand: 3600)")
      ->check(CLI::Range(0.001, 1e6));
  sub->add_option("--run", a->run_s, "simulated time of the other dynamic cases [s] (default 0.05, quick 0.02)")
      ->check(CLI::Range(0.001, 100.0));
  sub->add_option("--cases", a->cases, "run only these cases (comma-separated), e.g. --cases soak")->delimiter(',');
  sub->add_option("--script", a->script,
                  "script the soak loops (default: <scenario dir>/scripts/<scenario file> when written for the scene; none: no script)");
  sub->add_option("--report-every", a->report_every_s, "wall seconds between soak progress lines on stderr")
      ->check(CLI::Range(0.1, 86400.0))
      ->capture_default_str();
  sub->add_option("--checkpoint", a->checkpoint,
                  "soak only, one scenario: write the soak's state and figures to FILE every --checkpoint-every s of wall time "
                  "and at its end or when --budget runs out (atomic), so a long soak can go on later with --resume");
  sub->add_option("--checkpoint-every", a->checkpoint_every_s, "wall seconds between soak checkpoints")
      ->check(CLI::Range(1.0, 86400.0))
      ->capture_default_str();
  sub->add_option("--resume", a->resume,
                  "soak only, one scenario: go on from a checkpoint of the same scenario file and script (--soak is the total "
                  "simulated time, the checkpoint's included)");
  sub->add_option("--seed", a->seed, "seed of the random impulses and command sequences (replay a failure with it)")
      ->capture_default_str();
  sub->callback([a, &run] {
    run = [a]() -> int {
      StressOptions opt;
      opt.quick = a->quick;
      opt.budget_s = a->budget_s > 0 ? a->budget_s : (a->quick ? 12.0 : 60.0);
      opt.soak_s = a->soak_s > 0 ? a->soak_s : (a->quick ? 0.05 : 0.5);
      opt.run_s = a->run_s > 0 ? a->run_s : (a->quick ? 0.02 : 0.05);
      opt.seed = a->seed;
      opt.report_every_s = a->report_every_s;
      opt.soak_script = a->script;
      opt.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
      const std::vector<std::string> known = all_stress_case_names();
      for (const auto& c : a->cases)  // bad input: exit 2 before any case runs
        if (std::find(known.begin(), known.end(), c) == known.end())
          throw InputError("", 0, "--cases", "unknown stress case '" + c + "' (cases: stable_substep, stiff_inclusion_{10,100,1000}, "
                                              "needle_1m_s, gun_fired, pullback_stuck, probe_push_rotate, fill_max_rate, "
                                              "random_impulses, random_commands, soak)");
      opt.cases = a->cases;
      prepare_output_file(a->json, "--json");
      prepare_output_file(a->csv, "--csv");
      const std::vector<std::string> files = a->scenarios.empty() ? default_scenarios(a->root) : a->scenarios;
      if (!a->script.empty() && a->script != "none" && files.size() != 1)
        throw InputError("", 0, "--script", "--script needs exactly one scenario (each default scene has its own script)");
      for (const auto& [flag, value] : {std::pair<const char*, const std::string*>{"--checkpoint", &a->checkpoint}, {"--resume", &a->resume}})
        if (!value->empty() && (files.size() != 1 || a->cases != std::vector<std::string>{"soak"}))
          throw InputError("", 0, flag, std::string(flag) + " needs exactly one scenario and --cases soak");
      opt.checkpoint = a->checkpoint;
      opt.checkpoint_every_s = a->checkpoint_every_s;
      std::vector<ScenarioSpec> specs;
      std::vector<std::shared_ptr<const Model>> models;
      for (const auto& f : files) {
        specs.push_back(parse_scenario_file(f));
        models.push_back(compile_scenario(specs.back()));
        const std::string sf = soak_script_for(specs.back(), opt);
        if (!sf.empty()) {  // a bad or foreign script is bad input too
          const Script script = parse_script_file(sf);
          if (!script.scenario.empty() && script.scenario != specs.back().name)
            throw InputError(sf, 0, "scenario", "script written for scenario '" + script.scenario + "', not '" + specs.back().name + "'");
        }
      }
      if (!a->resume.empty()) {  // bad input (file, scenario, script) is exit 2 before the soak starts
        std::string taken_with;
        auto cp = std::make_shared<SoakCheckpoint>(read_soak_checkpoint(a->resume, taken_with));
        check_state_matches(cp->state, specs[0].name, file_content_hash(files[0]));
        const std::string sf = soak_script_for(specs[0], opt);
        namespace fs = std::filesystem;
        const bool same = sf.empty() ? taken_with.empty()
                                     : !taken_with.empty() && fs::exists(taken_with) && fs::equivalent(fs::path(sf), fs::path(taken_with));
        if (!same)
          throw InputError(a->resume, 2, "script", "checkpoint taken looping '" + (taken_with.empty() ? std::string("no script") : taken_with) +
                                                      "', this soak loops '" + (sf.empty() ? std::string("no script") : sf) + "'");
        if (cp->state.time >= opt.soak_s - 0.5 * models[0]->dt)
          throw InputError(a->resume, 0, "--soak", fmt_seconds(cp->state.time) + " already simulated: give a longer --soak to go on");
        opt.resume = cp;
      }
      int total = 0;
      for (const auto& s : specs) total += static_cast<int>(stress_case_names(s, opt).size());
      Progress progress("stress", total);
      int done = 0;
      std::vector<StressResult> all;
      std::printf("%-22s %-20s %-8s %8s %8s  %s\n", "scene", "case", "status", "sim_s", "wall_s", "tried / held");
      for (size_t si = 0; si < specs.size(); ++si) {
        const ScenarioSpec& s = specs[si];
        const auto rows = run_stress_cases(s, models[si], opt, [&](const std::string& item) { progress.update(done++, item); });
        progress.clear();
        for (const auto& r : rows) {
          std::printf("%-22s %-20s %-8s %8.4g %8.3g  %s\n%-62s -> %s\n", r.scene.c_str(), r.name.c_str(), r.status.c_str(), r.sim_s,
                      r.wall_s, r.tried.c_str(), "", r.held.c_str());
          std::fflush(stdout);
        }
        all.insert(all.end(), rows.begin(), rows.end());
      }
      progress.clear();
      int failed = 0, timeouts = 0;
      for (const auto& r : all) { failed += r.status == "FAIL"; timeouts += r.status == "TIMEOUT"; }
      if (!a->json.empty()) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& r : all) {
          nlohmann::json row = {{"scene", r.scene}, {"case", r.name}, {"status", r.status}, {"tried", r.tried},
                                {"held", r.held},   {"sim_s", r.sim_s}, {"wall_s", r.wall_s}};
          if (!r.figures.empty()) {
            nlohmann::json fig = nlohmann::json::object();
            for (const auto& [k, v] : r.figures) fig[k] = std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
            row["figures"] = fig;
          }
          j.push_back(row);
        }
        write_file_atomic(a->json, j.dump(2) + "\n");
      }
      if (!a->csv.empty()) {
        std::ostringstream o;
        o << "scene,case,status,sim_s,wall_s,tried,held\n";
        for (const auto& r : all)
          o << csv_field(r.scene) << ',' << csv_field(r.name) << ',' << r.status << ',' << r.sim_s << ',' << r.wall_s << ','
            << csv_field(r.tried) << ',' << csv_field(r.held) << '\n';
        write_file_atomic(a->csv, o.str());
      }
      std::printf("%zu cases: %d failed, %d ran out of time\n", all.size(), failed, timeouts);
      return failed + timeouts ? kExitFault : kExitOk;
    };
  });
}

}  // namespace ps::app
