// The trainee window's live implant dosimetry (issue 46): a worker thread, neither the physics
// thread nor the UI thread, brings the TG-43U1 dose grid up to date from a copy of the newest
// published Snapshot (the deposited seeds from its DrawList: capsules of role Seed, along their
// needles; the organs from its particle positions) and hands back the indices and the DVH
// (engine/dosimetry/live_dosimetry.h). The UI submits a snapshot when the seeds or the tick
// changed; while the worker is busy a newer submission replaces the waiting one.
#pragma once
#include <array>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/contract/snapshot.h"
#include "engine/dosimetry/live_dosimetry.h"
#include "engine/metrics/tracked_point.h"

namespace ps {
struct Scene;
}

namespace ps::gui {

struct DoseFrame {
  bool ready = false;
  int seeds = 0;
  double time = 0.0;                // simulation time of the snapshot [s]
  double ms = 0.0;                  // the update's compute time [ms]
  int seed_passes = 0;
  dosimetry::DosimetryIndices indices;
  dosimetry::DvhCurve dvh;
};

class DoseWorker {
 public:
  // Throws InputError when the scene has no gland surface (nothing to dose).
  explicit DoseWorker(const Scene& scene, const std::string& isotope = "I125_6711", double prescription_gy = 145.0,
                      double strength_u = 0.5);
  ~DoseWorker();
  DoseWorker(const DoseWorker&) = delete;
  DoseWorker& operator=(const DoseWorker&) = delete;

  void submit(const Snapshot& snap);
  bool take(DoseFrame& out);
  double prescription_gy() const { return rx_; }

 private:
  void run();
  const Model* model_;
  double rx_, strength_u_;
  std::vector<int> prostate_ids_, rectum_ids_;   // surface particles, in the faces' local order
  std::vector<TrackedPoint> urethra_;
  std::unique_ptr<dosimetry::LiveDosimetry> live_;
  std::mutex mu_;
  std::condition_variable cv_;
  struct Work {
    std::vector<float> x;
    std::vector<dosimetry::Seed> seeds;
    double time = 0.0;
  } pending_, working_;
  bool has_pending_ = false, stop_ = false, fresh_ = false;
  size_t last_seeds_ = static_cast<size_t>(-1);
  int64_t last_tick_ = -1;
  DoseFrame done_;
  std::thread thread_;
};

}  // namespace ps::gui
