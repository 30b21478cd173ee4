// What the `prostatesim` Python module (python/module.cpp) drives: a scene run in lock-step
// (engine/realtime/lockstep.h, the runner `replay` uses, so the same inputs give the same state
// hash), live commands parsed as script timeline entries (engine/realtime/script.h), snapshots,
// the TRUS planes from a snapshot, the needle session metrics, saved states. Plain C++: no
// Python here, so the module can release the GIL around step(). One mutex serialises callers.
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "engine/metrics/session_metrics.h"
#include "engine/realtime/lockstep.h"
#include "engine/sim/scene.h"
#include "engine/ultrasound/imager.h"

namespace ps::python {

class Session {
 public:
  // Loads and compiles the scenario (InputError / CompileError on bad input).
  explicit Session(const std::string& scenario_path);
  ~Session();

  // Runs `ticks` ticks. False when the physics faulted (fault_text() says where); it stays stopped.
  bool step(int64_t ticks);
  int64_t tick() const { return run_->tick(); }
  double time() const { return run_->time(); }
  double dt() const { return scene_.model->dt; }
  bool faulted() const { return run_->faulted(); }
  std::string fault_text() const { return run_->runner().fault_text(); }

  // A live command: the YAML/JSON text of a timeline entry without `t`, applied before the next
  // tick. InputError naming the key when it does not parse or names an instrument the scene
  // lacks; std::invalid_argument with the tool's reason when the tool refuses it.
  void command(const std::string& entry_text);

  const Scene& scene() const { return scene_; }
  const State& state() const { return scene_.sim->state(); }
  const Model& model() const { return *scene_.model; }
  ProbePose probe_pose() const;   // commanded so far (the scenario's start pose before any)

  Snapshot snapshot();             // of the current tick, events since the previous call
  // One TRUS plane of the current state ("transverse" or "sagittal"; InputError otherwise, or
  // when the scene has no probe).
  const us::UsImage& ultrasound(const std::string& view);
  // metrics.json of the needle session so far (InputError when the scene has no needles).
  std::string metrics_json() const;

  void save_state(const std::string& path);   // atomic (engine/realtime/state_file.h)
  void load_state(const std::string& path);   // InputError (file, field) when it does not fit
  uint64_t state_hash() { return run_->hash(); }

  std::mutex& mutex() { return mu_; }

 private:
  class MetricsFeed;
  Scene scene_;
  std::unique_ptr<LockstepRunner> run_;
  std::unique_ptr<MetricsFeed> metrics_;
  TimelineMemory timeline_;       // what the commands so far set (the probe pose)
  Snapshot snap_;
  std::unique_ptr<us::UltrasoundAnatomy> anatomy_;
  std::unique_ptr<us::BiplaneImager> imager_;
  std::mutex mu_;
};

}  // namespace ps::python
