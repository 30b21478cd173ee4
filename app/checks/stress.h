// `prostatesim stress`: the cases it runs on one scenario and the runner around them. Each case
// builds its own Simulation from the scene (plus the change it stresses), runs it under the
// Watchdog (engine/sim/watchdog.h) within a wall-clock budget, and reports what it tried and what
// held. A failure names the case, the simulated time and the particle; the next case still runs.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engine/model/model.h"
#include "engine/realtime/soak.h"
#include "engine/spec/scenario_spec.h"

namespace ps::app {

struct StressOptions {
  bool quick = false;
  double budget_s = 60.0;       // wall-clock budget of one case [s]
  double soak_s = 0.5;          // simulated time of the soak case [s]
  double run_s = 0.05;          // simulated time of the other dynamic cases [s]
  uint64_t seed = 1;            // random impulses / command sequences (replay with --seed)
  std::vector<std::string> cases;  // run only these (names as stress_case_names); empty: all
  // Script the soak loops: "" = the scene's own, <scenario dir>/scripts/<scenario file name>
  // when it exists and was written for the scene; "none" = no script; else a file.
  std::string soak_script;
  double report_every_s = 60.0; // wall time between soak progress lines [s]
  // The soak case writes its checkpoint here every checkpoint_every_s of wall time ("" none)
  // and goes on from `resume` when given (engine/realtime/soak_checkpoint.h; one scenario only).
  std::string checkpoint;
  double checkpoint_every_s = 300.0;
  std::shared_ptr<const SoakCheckpoint> resume;
  std::function<void(const std::string&)> progress;  // soak progress lines (null: quiet)
};

struct StressResult {
  // default member initializers: the cases fill a prefix ({scene, name} or five fields)
  std::string scene{}, name{};
  std::string tried{};          // what the case did, with numbers
  std::string held{};           // what held (or what broke: case, time, particle)
  std::string status{};         // held | FAIL | TIMEOUT | refused | skipped
  double sim_s = 0.0;           // simulated time reached [s]
  double wall_s = 0.0;          // wall time spent [s]
  std::vector<std::pair<std::string, double>> figures{};  // measured numbers (soak: drift) by name
  bool failed() const { return status == "FAIL" || status == "TIMEOUT"; }
};

// The script the soak case loops for `spec` under `opt` ("" when none; see soak_script).
std::string soak_script_for(const ScenarioSpec& spec, const StressOptions& opt);

// Every case name a scene can have (for --cases checking).
std::vector<std::string> all_stress_case_names();

// The case names in run order (for the progress bar and --list), opt.cases applied.
std::vector<std::string> stress_case_names(const ScenarioSpec& spec, const StressOptions& opt);

// Runs every case on one parsed scenario and its compiled model (compile it first, so bad input is
// exit 2 before any case). `on_case` is called before each case with its name.
std::vector<StressResult> run_stress_cases(const ScenarioSpec& spec, std::shared_ptr<const Model> model,
                                           const StressOptions& opt,
                                           const std::function<void(const std::string&)>& on_case);

}  // namespace ps::app
