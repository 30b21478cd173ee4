#include "app/frames/png_queue.h"

#include "engine/io/png_write.h"
#include "render/post_antialias.h"

namespace ps::frames {

PngQueue::PngQueue(int max_pending) : max_pending_(static_cast<size_t>(std::max(1, max_pending))) {
  thread_ = std::thread([this] { run(); });
}

PngQueue::~PngQueue() {
  {
    std::lock_guard<std::mutex> lk(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::vector<uint8_t> PngQueue::take_buffer() {
  std::lock_guard<std::mutex> lk(mu_);
  if (free_.empty()) return {};
  std::vector<uint8_t> b = std::move(free_.back());
  free_.pop_back();
  return b;
}

void PngQueue::push(const std::string& path, int w, int h, std::vector<uint8_t>&& rgb, int channels, bool fxaa) {
  std::unique_lock<std::mutex> lk(mu_);
  cv_.wait(lk, [&] { return jobs_.size() < max_pending_ || error_; });
  if (error_) std::rethrow_exception(error_);
  jobs_.push_back({path, w, h, channels, fxaa && channels == 3, std::move(rgb)});
  lk.unlock();
  cv_.notify_all();
}

void PngQueue::finish() {
  std::unique_lock<std::mutex> lk(mu_);
  cv_.wait(lk, [&] { return (jobs_.empty() && !busy_) || error_; });
  if (error_) std::rethrow_exception(error_);
}

int PngQueue::written() const {
  std::lock_guard<std::mutex> lk(mu_);
  return written_;
}

void PngQueue::run() {
  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> lk(mu_);
      cv_.wait(lk, [&] { return stop_ || !jobs_.empty(); });
      if (jobs_.empty()) return;  // stop requested and nothing left
      job = std::move(jobs_.front());
      jobs_.pop_front();
      busy_ = true;
    }
    std::exception_ptr err;
    try {
      const uint8_t* px = job.rgb.data();
      if (job.fxaa) {
        aa_out_.resize(job.rgb.size());
        render::fxaa_rgb(job.rgb.data(), job.w, job.h, aa_out_.data(), aa_luma_);
        px = aa_out_.data();
      }
      ps::write_png_atomic(job.path, job.w, job.h, job.channels, px);
    } catch (...) {
      err = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lk(mu_);
      busy_ = false;
      if (err && !error_) error_ = err;
      if (!err) ++written_;
      free_.push_back(std::move(job.rgb));
    }
    cv_.notify_all();
  }
}

}  // namespace ps::frames
