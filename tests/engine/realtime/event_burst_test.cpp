// A burst of events in one tick (engine/realtime/tick_runner.h fill_snapshot's max_events,
// physics_loop.h kEventCapacity): more events than a snapshot buffer holds are delivered over the
// next snapshots, in order, none lost and none twice, and publishing them allocates nothing
// (appending every pending event would grow the snapshot's vector on the physics thread).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/physics_loop.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

// A tool that raises `burst` events at the end of tick `at` (1-based) and nothing else; event k
// carries k in its depth, so the reader can check order and completeness.
class BurstTool final : public Tool {
 public:
  BurstTool(int64_t at, int burst) : at_(at), burst_(burst) {}
  const char* name() const override { return "burst"; }
  void after_step(const Model&, State&, double) override {
    if (step_context().last_substep && ++ticks_ == at_) produced_ += burst_;
  }
  int64_t events_since(int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out, size_t max_size) const override {
    for (int64_t k = cursor; k < produced_; ++k) {
      if (out.size() >= max_size) return k;
      SnapshotEvent e;
      e.tool = tool_index;
      e.depth = static_cast<double>(k);
      out.push_back(e);
    }
    return produced_;
  }
  void serialize(StateIO& io) override {
    io.pod(ticks_);
    io.pod(produced_);
  }

 private:
  int64_t at_;
  int burst_;
  int64_t ticks_ = 0, produced_ = 0;
};

constexpr int kBurst = 600;  // more than two snapshot buffers' worth

// What the reader met of the burst (event k carries k), and the allocations counted meanwhile.
struct BurstReader {
  std::vector<double> got;
  uint64_t taken = 0;  // newest seq taken
  long allocations = 0;
  BurstReader() { got.reserve(kBurst); }
  void take(const std::vector<SnapshotEvent>& events) {
    EXPECT_LE(events.size(), 256u);
    for (const SnapshotEvent& e : events)
      if (e.seq > taken) {
        got.push_back(e.depth);
        taken = e.seq;
      }
  }
  void expect_whole_in_order() const {
    EXPECT_EQ(allocations, 0);
    ASSERT_EQ(got.size(), static_cast<size_t>(kBurst)) << "events lost or repeated";
    for (int k = 0; k < kBurst; ++k) EXPECT_EQ(got[k], static_cast<double>(k)) << "event " << k << " out of order";
  }
};

TEST(EventBurst, FillSnapshotHoldsBackWhatExceedsTheBoundAndDeliversItNext) {
  Scene sc = test::make_live_scene();
  sc.sim->add_tool(std::make_unique<BurstTool>(2, kBurst));
  LockstepRunner run(*sc.sim);
  ASSERT_TRUE(run.step());
  Snapshot snap;
  snap.events.reserve(256);
  run.runner().fill_snapshot(snap);  // sizes positions, tools and draw lists once
  ASSERT_TRUE(run.step());           // the burst
  BurstReader reader;
  for (int call = 0; call < 4; ++call) {
    const long before = test::allocation_count();
    run.runner().fill_snapshot(snap, false, false, snap.events.capacity());
    reader.allocations += test::allocation_count() - before;
    // a fresh snapshot each call (keep_events false): every event in it is new
    if (!snap.events.empty()) EXPECT_GT(snap.events.front().seq, reader.taken);
    reader.take(snap.events);
  }
  EXPECT_EQ(snap.events.capacity(), 256u);
  reader.expect_whole_in_order();
}

// The threaded loop with a reader that takes every snapshot: the burst reaches it whole, in order,
// and no tick (the burst's included) allocates once the loop is warm.
TEST(EventBurst, ThePhysicsLoopPublishesABurstOverSeveralTicksWithoutAllocating) {
  Scene sc = test::make_live_scene();
  sc.sim->add_tool(std::make_unique<BurstTool>(5, kBurst));
  LoopOptions opt;
  opt.start_paused = true;
  opt.log_timing = false;
  PhysicsLoop loop(*sc.sim, opt);
  loop.start();
  BurstReader reader;
  for (int k = 0; k < 12; ++k) {
    const long before = test::allocation_count();
    loop.single_step(1);
    loop.wait_for_tick(k + 1);
    // the tick's snapshot is published right after its tick counter: give it that moment
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (k >= 3) reader.allocations += test::allocation_count() - before;  // ticks 1-3 fill each of the three buffers once
    if (loop.update_snapshot()) reader.take(loop.snapshot().events);
  }
  loop.stop();
  reader.expect_whole_in_order();
}

}  // namespace
}  // namespace ps
