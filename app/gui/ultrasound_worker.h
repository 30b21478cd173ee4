// The trainee window's live biplane TRUS images (issue 12 in the app): a worker thread, neither
// the physics thread nor the UI thread, forms both planes from a copy of the newest published
// Snapshot (probe pose, needles and seeds from its DrawList: engine/ultrasound/from_simulation.h)
// and hands back 8-bit images. The UI submits a snapshot each frame; while the worker is busy a
// newer submission replaces the waiting one (the panel shows the newest image it finished, at
// whatever rate the imager sustains, using at most a third of a core), so neither physics nor the
// UI ever waits on it.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/contract/snapshot.h"
#include "engine/dosimetry/isodose.h"
#include "engine/ultrasound/imager.h"

namespace ps {
struct Scene;
}

namespace ps::gui {

// The knobs a sonographer turns on the live image (issue 12: gain, depth and frequency adjustable).
struct UsControls {
  double gain_db = 0.0;          // overall gain [dB]
  double depth_m = 0.060;        // imaging depth [m]
  double frequency_hz = 7.5e6;   // centre frequency [Hz]
  bool lesions = true;           // lesions as a fused MRI contour on both planes
};

struct UsFrame {
  int side = 0;                          // square images [px]
  std::vector<uint8_t> transverse, sagittal;  // grayscale, rows top-down
  double time = 0.0;                     // simulation time of the snapshot [s]
  double ms = 0.0;                       // both planes' compute time [ms]
  dosimetry::PixelPlane plane[2];        // where the transverse and sagittal pixels are [mm] (isodose lines)
};

class UltrasoundWorker {
 public:
  // Builds the imaged anatomy of the scene (it must have a probe: has_probe()). `side` in px.
  UltrasoundWorker(const Scene& scene, int side = 384);
  ~UltrasoundWorker();
  UltrasoundWorker(const UltrasoundWorker&) = delete;
  UltrasoundWorker& operator=(const UltrasoundWorker&) = delete;

  // Copies the snapshot for the worker (never blocks on the imager).
  void submit(const Snapshot& snap);
  // True when a newer frame than the last taken one is ready; swaps it into `out`.
  bool take(UsFrame& out);
  // New gain, depth, frequency: checked here (InputError naming ultrasound.<field>, nothing
  // changed), applied by the worker before its next image (it rebuilds its imager for them).
  void set_controls(const UsControls& c);
  UsControls controls() const;

 private:
  void run();
  std::unique_ptr<us::UltrasoundAnatomy> anatomy_;
  std::unique_ptr<us::BiplaneImager> imager_;
  us::UltrasoundScene scene_;
  us::ProbeView probe_;
  us::UltrasoundSettings settings_, pending_settings_;  // current / waiting for the worker (guarded by mu_)
  bool settings_changed_ = false;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  Snapshot pending_, working_;
  bool has_pending_ = false, stop_ = false, fresh_ = false;
  UsFrame done_;
  std::thread thread_;
};

}  // namespace ps::gui
