// What a run of a scenario with its instruments does, tick by tick, for comparing a fast
// configuration against a converged reference run (docs/performance.md "Accuracy of the fast
// settings"): the needle's axial force, its punctures, the prostate's and a target particle's
// positions and the volume errors. Recording happens between ticks, never inside a step.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "engine/spec/scenario_spec.h"
#include "engine/step/simulation.h"

namespace ps {

struct PunctureRecord {
  int needle = -1;
  int component = -1;
  double time = 0.0;               // [s]
  double depth = 0.0;              // tip depth along the planned line at the breach [m]
  double force = 0.0;              // axial force at the breach [N]
};

struct Trajectory {
  double dt = 0.0;                 // tick [s]
  int substeps = 0;                // substeps per tick of the run
  std::vector<double> force;       // [ticks] axial tissue force on needle 0, tick average [N]
  std::vector<double> tip_depth;   // [ticks] tip depth of needle 0 along its planned line [m]
  std::vector<std::vector<Vec3>> watched;  // [ticks][watched particles] positions [m]
  std::vector<int> watched_particles;      // particle indices (the prostate's, then the target)
  int prostate_count = 0;          // the first prostate_count watched particles are the prostate's
  int target = -1;                 // the target particle (last watched)
  std::vector<PunctureRecord> punctures;
  double worst_volume_error = 0.0; // largest relative error of a constrained volume, any tick
  double max_tenting = 0.0;        // largest tip travel between contact and first breach [m]
  double evaluated_elements = 1.0; // mean over ticks of the fraction of tet elements evaluated
                                   // (below 1 when tissue sleeps, solver.sleep)
  bool faulted = false;
  std::string fault;
};

// Runs `spec` (compiled as `model`) with the tools its sections describe, for `duration` [s],
// recording every tick. The target is the particle nearest to `target_point` (its component's
// tags or a lesion, chosen by the caller) [m].
Trajectory record_trajectory(const ScenarioSpec& spec, std::shared_ptr<const Model> model, double duration,
                             const Vec3& target_point);

// Differences of `run` against `ref` (same scene, same particles, same tick).
struct TrajectoryError {
  double force_rms = 0.0;          // RMS over ticks of the axial force difference [N]
  double force_peak = 0.0;         // largest |force| of the reference [N]
  double puncture_depth = 0.0;     // largest |depth difference| over matched punctures [m]
  int puncture_mismatch = 0;       // punctures in one run and not in the other
  double prostate_rms = 0.0;       // max over ticks of the RMS position difference over the prostate [m]
  double prostate_max = 0.0;       // max over ticks and prostate particles [m]
  double target = 0.0;             // max over ticks of the target particle's position difference [m]
  double volume = 0.0;             // worst constrained-volume error of `run` [-]
};
TrajectoryError compare_trajectories(const Trajectory& run, const Trajectory& ref);

}  // namespace ps
