#include "app/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace ps::app {

Progress::Progress(std::string label, int total)
    : label_(std::move(label)), total_(std::max(1, total)), enabled_(isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()), last_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() {
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void Progress::update(int done, const std::string& item) {
  done_ = std::clamp(done, 0, total_);
  item_ = item;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(100) && done_ < total_) return;
  last_ = now;
  draw();
}

void Progress::clear() {
  if (enabled_) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }
}

void Progress::draw() {
  if (!enabled_) return;
  constexpr int kWidth = 30;
  const int filled = done_ * kWidth / total_;
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(filled, '#');
  bar.resize(kWidth, '.');
  std::string item = item_.size() > 40 ? item_.substr(0, 37) + "..." : item_;
  std::fprintf(stderr, "\r\033[K%s [%s] %d/%d %5.0fs %s", label_.c_str(), bar.c_str(), done_, total_, el, item.c_str());
  std::fflush(stderr);
}

}  // namespace ps::app
