// The snapshot handoff under a producer/consumer stress test: the writer never waits, the
// reader never sees a torn value (every word of a value carries the same sequence number),
// sequence numbers only go up, and a snapshot the reader skipped is reported to the writer so
// its events can be carried over.
#include "engine/realtime/triple_buffer.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>

namespace ps {
namespace {

struct Value {
  uint64_t seq = 0;
  std::array<uint64_t, 61> words{};   // a torn read would mix two sequence numbers
};

TEST(TripleBuffer, ReaderNeverSeesATornValueAndSequenceOnlyGrows) {
  TripleBuffer<Value> tb;
  constexpr uint64_t kPublishes = 300000;
  std::atomic<bool> done{false};
  std::atomic<uint64_t> torn{0}, backwards{0}, reads{0};
  std::thread reader([&] {
    uint64_t last = 0;
    while (!done.load(std::memory_order_acquire)) {
      if (!tb.update()) continue;
      const Value& v = tb.front();
      for (uint64_t w : v.words)
        if (w != v.seq) ++torn;
      if (v.seq < last) ++backwards;
      last = v.seq;
      ++reads;
    }
  });
  uint64_t skipped = 0, s = 0;
  // publish at least kPublishes values and until the reader has taken many of them (on a loaded
  // machine the reader may not be scheduled at first; the writer yields now and then so the two
  // really interleave), capped at 10 s
  const auto t0 = std::chrono::steady_clock::now();
  while (s < kPublishes || (reads.load() < 20000 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(10))) {
    ++s;
    Value& v = tb.back();
    v.seq = s;
    v.words.fill(s);
    skipped += tb.publish();
    if ((s & 63) == 0) std::this_thread::yield();
  }
  const uint64_t published = s;
  done.store(true, std::memory_order_release);
  reader.join();
  EXPECT_EQ(torn.load(), 0u);
  EXPECT_EQ(backwards.load(), 0u);
  EXPECT_GT(reads.load(), 1000u);
  // the last value is there to take
  tb.update();
  EXPECT_EQ(tb.front().seq, published);
  std::printf("%llu publishes, %llu reads, %llu skipped snapshots reported to the writer\n",
              static_cast<unsigned long long>(published), static_cast<unsigned long long>(reads.load()),
              static_cast<unsigned long long>(skipped));
}

TEST(TripleBuffer, PublishReportsASkippedValueExactly) {
  TripleBuffer<int> tb;
  tb.back() = 1;
  EXPECT_FALSE(tb.publish());   // the middle held nothing published
  tb.back() = 2;
  EXPECT_TRUE(tb.publish());    // 1 was never read: the writer gets it back
  EXPECT_EQ(tb.back(), 1);
  EXPECT_TRUE(tb.update());
  EXPECT_EQ(tb.front(), 2);
  EXPECT_FALSE(tb.update());    // nothing newer
  tb.back() = 3;
  EXPECT_FALSE(tb.publish());   // 2 was read
}

}  // namespace
}  // namespace ps
