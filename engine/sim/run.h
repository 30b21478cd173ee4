// Headless runs: advance a Simulation for a duration or until rest, collect what `simulate`
// reports. Wall-clock timing happens here, around the steps, never inside them.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "engine/step/simulation.h"

namespace ps {

struct RunOptions {
  double duration = 1.0;           // simulated time to run, or the cap with until_rest [s]
  bool until_rest = false;         // stop once kinetic energy < rest_energy for rest_hold
  double rest_energy = 1e-7;       // [J]
  double rest_hold = 0.05;         // [s]
};

struct RunResult {
  int64_t steps = 0;               // substeps taken
  double sim_time = 0.0;           // [s]
  double wall_time = 0.0;          // [s]
  double kinetic_energy = 0.0;     // [J]
  double max_speed = 0.0;          // [m/s]
  std::map<std::string, double> volume_error;  // component -> |V - V_target| / V_target
  std::vector<std::string> warnings;
  bool faulted = false;
  std::string fault;               // StepFault::describe when faulted
  bool at_rest = false;            // until_rest reached its criterion
};

RunResult run_simulation(Simulation& sim, const RunOptions& opt);

// Relative volume error of every component surface (constrained or not) against its target.
std::map<std::string, double> volume_errors(const Model& m, const State& s);

}  // namespace ps
