// Lock-free triple buffer: one writer (the physics thread) publishes whole values, one reader
// (render / UI) takes the newest. Neither ever waits: the writer fills its back buffer and swaps
// it with the middle one in one atomic exchange; the reader swaps the middle one in when it is
// newer than what it holds. The three buffers are allocated once (their contents keep capacity),
// so publishing does not allocate once warm. A reader never sees a torn value: the buffer it holds
// is out of the writer's reach until it swaps again.
//
// The middle slot's index and a "fresh" bit share one atomic byte. publish() tells the writer
// whether the value it got back had never been read, so it can carry that value's events over
// into the next one (no event is lost to a reader that skipped a snapshot).
//
// Memory order: the writer's exchange is acq_rel (release: its writes to the buffer happen before
// the reader's acquire of the same index; acquire: the buffer it gets back is no longer read).
#pragma once
#include <atomic>
#include <cstdint>

namespace ps {

template <class T>
class TripleBuffer {
 public:
  TripleBuffer() = default;
  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  // --- writer thread only ---
  T& back() { return buf_[back_]; }
  // Publishes back() and hands the writer another buffer. Returns true when the buffer handed
  // back holds a value that was published but never read (a skipped snapshot).
  bool publish() {
    const uint8_t old = middle_.exchange(static_cast<uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = old & kIndex;
    return (old & kFresh) != 0;
  }

  // --- reader thread only ---
  // Takes the newest published value if there is one newer than front(). Returns true if so.
  bool update() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const uint8_t old = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = old & kIndex;
    return true;
  }
  const T& front() const { return buf_[front_]; }
  T& front_mut() { return buf_[front_]; }

  // Setup only (before the threads start): every buffer, e.g. to reserve capacity.
  T& raw(int i) { return buf_[i]; }

 private:
  static constexpr uint8_t kIndex = 3, kFresh = 4;
  T buf_[3]{};
  alignas(64) std::atomic<uint8_t> middle_{1};
  alignas(64) uint8_t back_ = 0;    // writer's
  alignas(64) uint8_t front_ = 2;   // reader's
};

}  // namespace ps
