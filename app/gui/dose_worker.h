// The trainee window's live implant dosimetry (issue 46): a worker thread, neither the physics
// thread nor the UI thread, brings the TG-43U1 dose grid up to date from a copy of the newest
// published Snapshot (app/frames/snapshot_dose.h: the deposited seeds from its DrawList, the
// organs from its particle positions) and hands back the indices, the DVH, a copy of the grid
// (the TRUS panel draws the isodose lines of both planes from it) and the prescription isodose
// surface (engine/dosimetry/isodose.h; the 3D view draws it translucent). The UI submits a
// snapshot when the seeds or the tick changed; while the worker is busy a newer submission
// replaces the waiting one.
#pragma once
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "app/frames/snapshot_dose.h"
#include "engine/contract/snapshot.h"

namespace ps::gui {

struct DoseFrame {
  bool ready = false;
  int seeds = 0;
  double time = 0.0;                // simulation time of the snapshot [s]
  double ms = 0.0;                  // the update's compute time: grid, masks, indices, DVH [ms]
  double iso_ms = 0.0;              // the grid's copy and the prescription isodose surface [ms]
  int seed_passes = 0;
  dosimetry::DosimetryIndices indices;
  dosimetry::DvhCurve dvh;
  std::shared_ptr<const dosimetry::DoseField> field;       // the grid at that time
  std::shared_ptr<const dosimetry::IsoSurface> surface;    // D = prescription [mm]; empty before a seed
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
  double rx_;
  frames::SnapshotDose dose_;
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
  std::vector<dosimetry::Seed> scratch_;
  DoseFrame done_;
  std::thread thread_;
};

}  // namespace ps::gui
