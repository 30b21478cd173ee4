// Fixed-capacity single-producer / single-consumer lock-free ring of trivially copyable values
// (the recorder's ring of applied commands and periodic state hashes; CommandQueue is the same
// design for Commands). No allocation after construction, no lock, neither side waits: push()
// on a full ring returns false, pop() on an empty one returns false. Memory order as in
// engine/realtime/command_queue.h (release store of the index after the slot is written).
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace ps {

template <class T>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  explicit SpscRing(size_t capacity) : slots_(capacity) {
    if (capacity == 0) throw std::invalid_argument("SpscRing: capacity must be > 0");
  }
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  bool push(const T& v) {  // producer only
    const uint64_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) >= slots_.size()) return false;
    slots_[h % slots_.size()] = v;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }
  bool pop(T& out) {  // consumer only
    const uint64_t t = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == t) return false;
    out = slots_[t % slots_.size()];
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }
  size_t capacity() const { return slots_.size(); }

 private:
  std::vector<T> slots_;
  alignas(64) std::atomic<uint64_t> head_{0};
  alignas(64) std::atomic<uint64_t> tail_{0};
};

}  // namespace ps
