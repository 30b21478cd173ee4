#include "app/gui/dose_worker.h"

#include <chrono>

namespace ps::gui {

DoseWorker::DoseWorker(const Scene& scene, const std::string& isotope, double rx, double strength_u)
    : rx_(rx), dose_(scene, isotope, rx, strength_u) {
  thread_ = std::thread([this] { run(); });
}

DoseWorker::~DoseWorker() {
  {
    std::lock_guard<std::mutex> lk(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DoseWorker::submit(const Snapshot& snap) {
  dose_.seeds_of(snap, scratch_);
  // a new update when a seed dropped, else every 25 ticks (the tissue carries the seeds)
  if (scratch_.size() == last_seeds_ && snap.tick - last_tick_ < 25) return;
  last_seeds_ = scratch_.size();
  last_tick_ = snap.tick;
  std::lock_guard<std::mutex> lk(mu_);
  pending_.x = snap.x;
  pending_.time = snap.time;
  pending_.seeds = scratch_;
  has_pending_ = true;
  cv_.notify_one();
}

bool DoseWorker::take(DoseFrame& out) {
  std::lock_guard<std::mutex> lk(mu_);
  if (!fresh_) return false;
  out = done_;
  fresh_ = false;
  return true;
}

void DoseWorker::run() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lk(mu_);
      cv_.wait(lk, [&] { return stop_ || has_pending_; });
      if (stop_) return;
      std::swap(working_, pending_);
      has_pending_ = false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const dosimetry::LiveDosimetry::Result* r = nullptr;
    try {
      r = &dose_.update(working_.x, working_.seeds);
    } catch (const std::exception&) {
      continue;  // a snapshot of another model (the session switched): the next one
    }
    const auto t1 = std::chrono::steady_clock::now();
    std::shared_ptr<const dosimetry::DoseField> field = dose_.field();
    auto surface = std::make_shared<dosimetry::IsoSurface>();
    if (!working_.seeds.empty()) *surface = dosimetry::isodose_surface(*field, rx_, dosimetry::kViewSurfaceStride);
    const auto t2 = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lk(mu_);
    done_.ready = true;
    done_.seeds = static_cast<int>(working_.seeds.size());
    done_.time = working_.time;
    done_.ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    done_.iso_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    done_.seed_passes = r->seed_passes;
    done_.indices = r->indices;
    done_.dvh = r->dvh;
    done_.field = std::move(field);
    done_.surface = std::move(surface);
    fresh_ = true;
  }
}

}  // namespace ps::gui
