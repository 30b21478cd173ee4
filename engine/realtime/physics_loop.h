// The physics thread: a fixed tick (the scenario's dt, model.substeps substeps each), kept in
// step with the wall clock, publishing a Snapshot after every tick through a lock-free triple
// buffer (engine/realtime/triple_buffer.h). The UI thread reads snapshots and pushes commands
// (queue(), stamped with next_tick()); devices and scripts are CommandSources polled each tick.
//
// Real-time sync (MuJoCo's simulate pattern): tick k of a run anchored at wall time W0 and tick K0
// is due at W0 + (k - K0) * dt / factor, computed from the anchor (no accumulated sleep error, so
// no drift). When a tick finishes later than max_lag behind its due time (the scene is heavier
// than real time at this factor), the loop re-anchors at now instead of trying to catch up (no
// spiral of death) and reports slow motion with the real-time factor it achieves.
// Controls (any thread, never blocking the physics): pause, resume, single-step, reset (back to
// the initial state, sources rewound), slow-motion factor, stop.
// Timing (timing()): achieved tick rate, real-time factor, p50/p99/max compute per tick over the
// last window, overruns, per-stage time (every 32nd tick is timed stage by stage through a
// StageProbe; the clock is read here, never in engine/step), logged with spdlog at most once a
// second (log_timing).
// Nothing here allocates per tick once warm (the snapshot buffers keep their capacity).
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

#include "engine/contract/snapshot.h"
#include "engine/realtime/tick_runner.h"
#include "engine/realtime/triple_buffer.h"

namespace ps {

struct LoopTiming {
  int64_t ticks = 0;               // ticks completed since start (or reset)
  double sim_time = 0.0;           // [s]
  double achieved_hz = 0.0;        // ticks per wall second over the last window
  double realtime_factor = 0.0;    // simulated seconds per wall second over the last window
  double target_factor = 1.0;      // the chosen slow-motion factor (1 = real time)
  bool slow_motion = false;        // the loop could not keep target_factor in the last window
  double tick_p50_ms = 0.0;        // compute time of a tick (commands + physics), last window [ms]
  double tick_p99_ms = 0.0;
  double tick_max_ms = 0.0;
  double jitter_ms = 0.0;          // p99 - p50 of the interval between tick starts, last window [ms]
  // the same over every tick since start (or reset), from a histogram of 10 us bins [ms]
  double run_tick_p50_ms = 0.0, run_tick_p99_ms = 0.0, run_tick_max_ms = 0.0;
  int64_t overruns = 0;            // ticks whose compute exceeded their period (since start)
  int64_t reanchors = 0;           // times the loop gave up catching up (slow motion)
  double publish_ms = 0.0;         // mean snapshot fill + publish per tick, last window [ms]
  std::array<double, kStageCount> stage_ms{};  // mean per tick of each Stage, sampled ticks [ms]
  int64_t commands_applied = 0, commands_refused = 0, commands_late = 0;
  bool paused = false;
  bool faulted = false;
};

struct LoopOptions {
  double factor = 1.0;             // slow motion: simulated seconds per wall second (<= 1 slower)
  double max_lag = 0.1;            // re-anchor when this far behind [s wall]
  bool log_timing = true;          // spdlog info once a second
  int64_t stop_at_tick = -1;       // pause by itself at this tick (headless --duration), -1 never
  bool start_paused = false;
  bool as_fast_as_possible = false;  // no pacing (benchmarks of the raw tick rate)
};

class PhysicsLoop {
 public:
  PhysicsLoop(Simulation& sim, LoopOptions opt = {});
  ~PhysicsLoop();  // stops the thread
  PhysicsLoop(const PhysicsLoop&) = delete;
  PhysicsLoop& operator=(const PhysicsLoop&) = delete;

  // Before start(): devices, scripts, the recorder (CommandApplier::set_observer via applier(),
  // set_hash_observer), recovery (set_watchdog, keep_last_good; TickRunner has the details).
  void add_source(CommandSource* s) { runner_.add_source(s); }
  CommandApplier& applier() { return runner_.applier(); }
  void set_watchdog(const Watchdog* w) { runner_.set_watchdog(w); }
  void keep_last_good(bool on) { runner_.keep_last_good(on); }
  // the loop spreads each hash over the following ticks (TickRunner::spread_hashes): a recording's
  // full-state hash every 100 ticks would otherwise add ~1.5 ms to one tick in a hundred
  void set_hash_observer(HashObserver* o, int every) {
    runner_.set_hash_observer(o, every);
    runner_.spread_hashes(o != nullptr && every > 0);
  }
  void inject_fault(int64_t tick, int particle = 0, bool internal = false) { runner_.inject_fault(tick, particle, internal); }  // tests

  void start();
  void stop();                     // joins the physics thread (idempotent)
  bool running() const { return running_.load(std::memory_order_acquire); }

  // --- controls (any thread) ---
  void pause() { paused_.store(true, std::memory_order_release); }
  void resume() { paused_.store(false, std::memory_order_release); }
  bool paused() const { return paused_.load(std::memory_order_acquire); }
  void single_step(int n = 1) { step_requests_.fetch_add(n, std::memory_order_acq_rel); }
  void reset() { reset_requested_.store(true, std::memory_order_release); }
  // Goes on from a saved state (TickRunner::load_state; check_state_matches first). Blocks the
  // caller (never the physics) until the physics thread has loaded it between two ticks, or
  // loads it at once when the thread is not running. The fault, if any, is cleared; a paused
  // loop stays paused. Throws InputError (file, field) with nothing changed when it does not fit.
  void load_state(const SavedState& st);
  // The current state (the owner, while the loop is stopped: `run` at the end).
  void current_state(SavedState& out) { runner_.current_state(out); }
  void set_factor(double f);       // clamped to [1e-3, 100]
  double factor() const { return factor_.load(std::memory_order_relaxed); }

  // --- UI thread: commands (one producer) ---
  CommandQueue& queue() { return runner_.queue(); }
  int64_t next_tick() const { return tick_.load(std::memory_order_acquire); }  // stamp for a push

  // --- reader thread (one): snapshots ---
  // Takes the newest snapshot if there is a newer one; true if so.
  bool update_snapshot() { return snaps_.update(); }
  const Snapshot& snapshot() const { return snaps_.front(); }

  int64_t tick() const { return tick_.load(std::memory_order_acquire); }   // ticks completed
  bool faulted() const { return faulted_.load(std::memory_order_acquire); }
  // After a fault (any thread): what stopped the physics (tick, time, kind, particle), and the
  // last good state (false when keep_last_good is off or nothing faulted). Copied by the physics
  // thread when it faults, so reading them never races with it; reset() clears them.
  std::string fault_text() const;
  bool last_good_state(SavedState& out) const;
  // An exception escaped a tick on the physics thread (a bug: a broken invariant, out of memory):
  // the thread catches it instead of terminating the program, stops the physics (faulted()), and
  // this says what (empty when none). The owner treats it as an internal error (exit 4).
  bool internal_error() const { return internal_.load(std::memory_order_acquire); }
  // Blocks the caller (not the physics) until the loop reached `tick`, faulted or stopped.
  void wait_for_tick(int64_t tick) const;
  LoopTiming timing() const;       // copy of the last window's figures
  // The simulation, for the owner only while the loop is stopped or paused and idle (hash at
  // the end of a run).
  Simulation& sim() { return runner_.sim(); }

 private:
  void thread_main();
  void thread_loop();
  void publish();
  void update_window(double wall_now, bool force);

  LoopOptions opt_;
  TickRunner runner_;
  TripleBuffer<Snapshot> snaps_;
  std::thread thread_;
  std::atomic<bool> running_{false}, stop_{false}, paused_{false}, reset_requested_{false}, faulted_{false}, internal_{false};
  std::atomic<int> step_requests_{0};
  std::atomic<double> factor_{1.0};
  std::atomic<int64_t> tick_{0};
  // timing window (physics thread)
  static constexpr int kWindow = 2048;
  std::array<float, kWindow> tick_ms_{}, interval_ms_{};
  // every tick's compute time since start or reset: 10 us bins, the last one open-ended
  static constexpr int kRunBins = 2000;
  std::array<int64_t, kRunBins> run_hist_{};
  double run_max_ms_ = 0.0;
  int window_n_ = 0;
  bool window_reported_ = false;   // a whole window's figures are in timing_ (the closing update keeps them)
  double window_start_ = 0.0;      // wall [s]
  int64_t window_tick0_ = 0;
  double window_sim0_ = 0.0;
  double publish_acc_ = 0.0;
  int publish_n_ = 0;
  std::array<double, kStageCount> stage_acc_{};
  int stage_samples_ = 0;
  double last_tick_start_ = -1.0;
  int64_t overruns_ = 0, reanchors_ = 0;
  bool lagging_ = false;
  // Events published that the reader may not have taken (in seq order; at most kMaxUnread, the
  // oldest dropped beyond it). Each snapshot carries them ahead of its own, so a reader that skips
  // snapshots still meets every event, in order (publish()).
  static constexpr size_t kMaxUnread = 128;
  // Each snapshot buffer's and unread_'s reserved event capacity: the carried kMaxUnread and at
  // least as many new ones per publish (TickRunner::fill_snapshot holds the rest back)
  static constexpr size_t kEventCapacity = 2 * kMaxUnread;
  std::vector<SnapshotEvent> unread_;
  uint64_t published_seq_ = 0;     // the newest event seq in the snapshot published last
  mutable std::mutex timing_mu_;   // the physics thread only try_locks it
  LoopTiming timing_;
  mutable std::mutex fault_mu_;    // guards the two below (the physics thread locks it only on a fault or reset)
  std::string fault_text_;
  SavedState fault_state_;
  bool have_fault_state_ = false;
  // a saved state to load (UI thread -> physics thread): 0 none, 1 asked, 2 done
  std::mutex load_mu_;
  std::atomic<int> load_step_{0};
  const SavedState* load_req_ = nullptr;
  std::exception_ptr load_error_;
  void do_load();                  // the physics thread, between ticks
};

}  // namespace ps
