// Compiled scenes are cached per process (compiling the 10k cube takes a while); each benchmark
// run builds its own Simulation from the cached Model and warms it up so the state is deformed.
//
// Under gravity the larger cubes sag without bound and eventually fault (a property of the model
// at this stiffness, not of the step: docs/performance.md), so a benchmark restores the warmed
// state every kCycle substeps: every timed step sees a body sagging in its first ~0.03 s. The
// restore is a copy into already-sized vectors (no allocation), ~0.1% of the steps it spans.
#pragma once
#include <map>
#include <memory>
#include <string>

#include "bench/scenes.h"
#include "engine/step/simulation.h"

namespace ps::bench {

inline std::shared_ptr<const Model> cached_scene(const std::string& name) {
  static std::map<std::string, std::shared_ptr<const Model>> cache;
  auto& m = cache[name];
  if (!m) m = scene_by_name(name);
  return m;
}

// Substep the compiler chose for the scene (model.dt / model.substeps) [s].
inline double substep(const Model& m) { return m.dt / m.substeps; }

inline constexpr int kWarm = 50;    // substeps before the snapshot
inline constexpr int kCycle = 150;  // substeps between restores

// Simulation of the scene after kWarm substeps (sagging under gravity, volume solve active).
inline std::unique_ptr<Simulation> warmed(const std::string& name) {
  auto sim = std::make_unique<Simulation>(cached_scene(name));
  const double h = substep(sim->model());
  for (int i = 0; i < kWarm; ++i) sim->step(h);
  return sim;
}

// Steps a warmed simulation with the compiler's substep, restoring the snapshot every kCycle.
class CyclingRun {
 public:
  explicit CyclingRun(const std::string& name) : sim_(warmed(name)), snapshot_(sim_->state()), h_(substep(sim_->model())) {}
  Simulation& sim() { return *sim_; }
  double h() const { return h_; }
  // call before each step; restores the snapshot when the cycle is over
  void maybe_restore() {
    if (++since_ > kCycle) { sim_->state() = snapshot_; since_ = 1; }
  }

 private:
  std::unique_ptr<Simulation> sim_;
  State snapshot_;
  double h_;
  int since_ = 0;
};

}  // namespace ps::bench
