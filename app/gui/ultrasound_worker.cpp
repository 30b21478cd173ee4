#include "app/gui/ultrasound_worker.h"

#include <chrono>

#include "app/frames/us_isodose.h"
#include "engine/sim/scene.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/util/error.h"

namespace ps::gui {

UltrasoundWorker::UltrasoundWorker(const Scene& scene, int side) {
  if (!scene.spec.probe) throw InputError(scene.spec.file, 0, "probe", "no probe: section to image from");
  anatomy_ = std::make_unique<us::UltrasoundAnatomy>(us::anatomy_for_scenario(scene.spec, *scene.model));
  us::UltrasoundSettings set = us::settings_for_probe(*scene.spec.probe);
  set.width = set.height = side;
  imager_ = std::make_unique<us::BiplaneImager>(*anatomy_, set);
  settings_ = pending_settings_ = set;
  done_.side = side;
  thread_ = std::thread([this] { run(); });
}

UltrasoundWorker::~UltrasoundWorker() {
  {
    std::lock_guard<std::mutex> lk(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void UltrasoundWorker::submit(const Snapshot& snap) {
  {
    std::lock_guard<std::mutex> lk(mu_);
    pending_ = snap;  // vector assignment keeps capacity: no allocation once warm
    has_pending_ = true;
  }
  cv_.notify_one();
}

void UltrasoundWorker::set_controls(const UsControls& c) {
  std::lock_guard<std::mutex> lk(mu_);
  us::UltrasoundSettings set = pending_settings_;
  set.gain_db = c.gain_db;
  set.depth = c.depth_m;
  set.frequency = c.frequency_hz;
  set.lesion_contours = c.lesions;
  us::validate(set);  // throws before anything changes
  pending_settings_ = set;
  settings_changed_ = true;
}

UsControls UltrasoundWorker::controls() const {
  std::lock_guard<std::mutex> lk(mu_);
  return {pending_settings_.gain_db, pending_settings_.depth, pending_settings_.frequency, pending_settings_.lesion_contours};
}

bool UltrasoundWorker::take(UsFrame& out) {
  std::lock_guard<std::mutex> lk(mu_);
  if (!fresh_) return false;
  std::swap(out, done_);
  fresh_ = false;
  return true;
}

void UltrasoundWorker::run() {
  UsFrame img;
  img.side = done_.side;
  bool rebuild = false;
  for (;;) {
    {
      std::unique_lock<std::mutex> lk(mu_);
      cv_.wait(lk, [&] { return stop_ || has_pending_; });
      if (stop_) return;
      std::swap(pending_, working_);
      has_pending_ = false;
      if (settings_changed_) {
        settings_ = pending_settings_;
        settings_changed_ = false;
        rebuild = true;
      }
    }
    if (rebuild) {  // new knobs: a new imager (its buffers and tables depend on depth and frequency)
      imager_ = std::make_unique<us::BiplaneImager>(*anatomy_, settings_);
      rebuild = false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    us::probe_view_from_snapshot(working_, probe_);  // no probe drawn: keeps the last pose
    us::scene_from_snapshot(working_, probe_, scene_);
    imager_->render(scene_);
    // every frame says its size: the frames circulate between this thread and the UI by swaps,
    // and the UI's first (empty, size 0) comes back here to be refilled
    img.side = imager_->transverse().image().width;
    img.transverse = imager_->transverse().image().pixels;
    img.sagittal = imager_->sagittal().image().pixels;
    img.plane[0] = frames::pixel_plane(imager_->transverse(), probe_);
    img.plane[1] = frames::pixel_plane(imager_->sagittal(), probe_);
    img.time = working_.time;
    img.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    {
      std::unique_lock<std::mutex> lk(mu_);
      std::swap(done_, img);
      fresh_ = true;
      // duty cycle <= 1/3 of a core: on a 2-core machine the physics and UI threads come first
      // (the images refresh at ~1000 / (3 x compute ms) Hz: ~17 Hz at 20 ms for both planes)
      cv_.wait_for(lk, std::chrono::duration<double, std::milli>(2.0 * done_.ms), [&] { return stop_; });
      if (stop_) return;
    }
  }
}

}  // namespace ps::gui
