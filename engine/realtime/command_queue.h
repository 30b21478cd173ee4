// Fixed-capacity single-producer / single-consumer lock-free ring of Commands: one thread (the
// user interface) pushes, one thread (the physics loop) pops. No allocation after construction,
// no lock, neither side ever waits: push() on a full ring returns false and counts the refusal
// (the producer decides whether to retry or drop; the physics never blocks on the UI), pop() on
// an empty ring returns false.
//
// Memory order: the producer writes the slot, then publishes it with a release store of head_;
// the consumer's acquire load of head_ makes the slot visible before it reads it (and the same
// the other way round for tail_, so a slot is not overwritten while being read). head_ and
// tail_ count pushes and pops without wrapping back (64-bit); the slot is count % capacity.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <new>
#include <stdexcept>
#include <vector>

#include "engine/contract/command.h"

namespace ps {

class CommandQueue {
 public:
  explicit CommandQueue(size_t capacity) : slots_(capacity) {
    if (capacity == 0) throw std::invalid_argument("CommandQueue: capacity must be > 0");
  }
  CommandQueue(const CommandQueue&) = delete;
  CommandQueue& operator=(const CommandQueue&) = delete;

  // Producer thread only. False (and counted in rejected()) when the ring is full.
  bool push(const Command& c) {
    const uint64_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) >= slots_.size()) {
      rejected_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    slots_[h % slots_.size()] = c;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }

  // Consumer thread only: the oldest command without removing it. False when empty.
  bool peek(Command& out) const {
    const uint64_t t = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == t) return false;
    out = slots_[t % slots_.size()];
    return true;
  }
  // Consumer thread only: removes the oldest command (after peek, or to read it). False when empty.
  bool pop(Command& out) {
    if (!peek(out)) return false;
    tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    return true;
  }

  size_t capacity() const { return slots_.size(); }
  // Approximate from another thread, exact from either side when the other is idle.
  size_t size() const { return static_cast<size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire)); }
  uint64_t rejected() const { return rejected_.load(std::memory_order_relaxed); }

 private:
  std::vector<Command> slots_;  // sized once
  // producer and consumer indices on separate cache lines (no false sharing)
  alignas(64) std::atomic<uint64_t> head_{0};   // pushes so far (producer writes)
  alignas(64) std::atomic<uint64_t> tail_{0};   // pops so far (consumer writes)
  alignas(64) std::atomic<uint64_t> rejected_{0};
};

}  // namespace ps
