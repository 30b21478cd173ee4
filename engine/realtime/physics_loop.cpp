#include "engine/realtime/physics_loop.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "engine/util/error.h"

namespace ps {

namespace {
using Clock = std::chrono::steady_clock;
double wall_s() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

// Times each stage of a sampled tick (the clock lives here, not in engine/step).
class StageTimer final : public StageProbe {
 public:
  explicit StageTimer(std::array<double, kStageCount>& acc) : acc_(acc) {}
  void begin(int) override { t0_ = Clock::now(); }
  void end(int stage) override {
    if (stage >= 0 && stage < kStageCount) acc_[stage] += std::chrono::duration<double, std::milli>(Clock::now() - t0_).count();
  }

 private:
  std::array<double, kStageCount>& acc_;
  Clock::time_point t0_;
};

// p-quantile of the first n values (partial sort of a stack copy: no allocation)
template <size_t N>
double quantile(const std::array<float, N>& v, int n, double p) {
  if (n <= 0) return 0.0;
  std::array<float, N> c;
  std::copy(v.begin(), v.begin() + n, c.begin());
  const int k = std::min(n - 1, static_cast<int>(p * (n - 1) + 0.5));
  std::nth_element(c.begin(), c.begin() + k, c.begin() + n);
  return c[k];
}
// p-quantile of a histogram of 10 us bins [ms] (the upper edge of the bin it falls in)
template <size_t N>
double hist_quantile(const std::array<int64_t, N>& h, double p) {
  int64_t n = 0;
  for (int64_t c : h) n += c;
  if (n == 0) return 0.0;
  const int64_t k = std::min<int64_t>(n - 1, static_cast<int64_t>(p * (n - 1) + 0.5));
  int64_t seen = 0;
  for (size_t b = 0; b < N; ++b) {
    seen += h[b];
    if (seen > k) return (b + 1) * 0.01;
  }
  return N * 0.01;
}
}  // namespace

PhysicsLoop::PhysicsLoop(Simulation& sim, LoopOptions opt) : opt_(opt), runner_(sim) {
  set_factor(opt.factor);
  paused_.store(opt.start_paused);
  // size the snapshot buffers once (positions, tools, events) so publishing does not allocate
  for (int i = 0; i < 3; ++i) {
    Snapshot& s = snaps_.raw(i);
    s.x.reserve(3 * sim.state().x.size());
    s.tools.reserve(sim.tools().size());
    s.events.reserve(kEventCapacity);
  }
  unread_.reserve(kEventCapacity);
}

PhysicsLoop::~PhysicsLoop() { stop(); }

void PhysicsLoop::set_factor(double f) {
  if (!(f > 0.0)) f = 1.0;
  factor_.store(std::clamp(f, 1e-3, 100.0), std::memory_order_relaxed);
}

void PhysicsLoop::start() {
  if (running_.load()) return;
  stop_.store(false);
  running_.store(true, std::memory_order_release);
  // the first snapshot (tick 0) is there before the thread runs
  publish();
  thread_ = std::thread([this] { thread_main(); });
}

void PhysicsLoop::stop() {
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  runner_.finish_hashes();  // a periodic hash still being spread over ticks (set_hash_observer)
  running_.store(false, std::memory_order_release);
}

void PhysicsLoop::wait_for_tick(int64_t t) const {
  while (tick() < t && !faulted() && running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

std::string PhysicsLoop::fault_text() const {
  std::lock_guard<std::mutex> g(fault_mu_);
  return fault_text_;
}

bool PhysicsLoop::last_good_state(SavedState& out) const {
  std::lock_guard<std::mutex> g(fault_mu_);
  if (!have_fault_state_) return false;
  out = fault_state_;
  return true;
}

void PhysicsLoop::load_state(const SavedState& st) {
  std::lock_guard<std::mutex> one(load_mu_);  // one load at a time
  load_req_ = &st;
  load_error_ = nullptr;
  if (!running() || !thread_.joinable()) {
    do_load();
  } else {
    load_step_.store(1, std::memory_order_release);
    while (load_step_.load(std::memory_order_acquire) != 2 && running() && !internal_error())
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (load_step_.load(std::memory_order_acquire) != 2) {
      load_step_.store(0, std::memory_order_release);
      throw InputError(st.file, 0, "", "the physics thread stopped before the state was loaded");
    }
  }
  load_step_.store(0, std::memory_order_release);
  load_req_ = nullptr;
  if (load_error_) std::rethrow_exception(load_error_);
}

void PhysicsLoop::do_load() {
  try {
    runner_.load_state(*load_req_);
  } catch (...) {
    load_error_ = std::current_exception();
    return;
  }
  {
    std::lock_guard<std::mutex> g(fault_mu_);
    fault_text_.clear();
    have_fault_state_ = false;
  }
  tick_.store(runner_.tick(), std::memory_order_release);
  faulted_.store(false, std::memory_order_release);
  unread_.clear();
  publish();  // readers see the loaded state at once (before start(): start() publishes again)
}

LoopTiming PhysicsLoop::timing() const {
  std::lock_guard<std::mutex> g(timing_mu_);
  return timing_;
}

void PhysicsLoop::publish() {
  const auto t0 = Clock::now();
  // The snapshot carries the events the reader may not have taken, then the new ones. Carrying
  // only the events of the buffer handed back would lose their order when the reader skips two
  // snapshots in a row: the skipped snapshot's events would sit in the middle buffer while the
  // next one went out without them, and reach the reader after it.
  Snapshot& b = snaps_.back();
  const size_t carried = unread_.size();
  b.events.assign(unread_.begin(), unread_.end());  // capacity reserved: no allocation
  runner_.fill_snapshot(b, true, false, kEventCapacity);
  unread_.insert(unread_.end(), b.events.begin() + static_cast<std::ptrdiff_t>(carried), b.events.end());
  if (unread_.size() > kMaxUnread) unread_.erase(unread_.begin(), unread_.end() - static_cast<std::ptrdiff_t>(kMaxUnread));
  const uint64_t newest = b.events.empty() ? published_seq_ : b.events.back().seq;
  // the buffer handed back was taken by the reader unless it is the previous snapshot, unread:
  // then the reader has every event up to that snapshot's newest
  if (!snaps_.publish()) {
    size_t k = 0;
    while (k < unread_.size() && unread_[k].seq <= published_seq_) ++k;
    unread_.erase(unread_.begin(), unread_.begin() + static_cast<std::ptrdiff_t>(k));
  }
  published_seq_ = newest;
  publish_acc_ += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  ++publish_n_;
}

void PhysicsLoop::update_window(double now, bool force) {
  const double span = now - window_start_;
  if (!force && span < 1.0) return;
  std::unique_lock<std::mutex> g(timing_mu_, std::try_to_lock);
  if (!g.owns_lock()) return;  // a reader holds it: try again next tick, never wait
  LoopTiming& t = timing_;
  const Simulation& sim = runner_.sim();
  t.ticks = runner_.tick();
  t.sim_time = sim.state().time;
  const int64_t dticks = runner_.tick() - window_tick0_;
  // the closing update (force) often finds a window that has just begun, with no tick or a few in
  // it: it keeps the last whole window's figures (not 0 ticks/s and a 0 ms p99 at stop) and
  // updates only the running totals below; a run shorter than a window reports its own
  const bool window_figures = !force || !window_reported_ || (window_n_ > 0 && dticks > 0 && span >= 0.25);
  if (window_figures) {
    window_reported_ = true;
    t.achieved_hz = span > 0 ? dticks / span : 0.0;
    t.realtime_factor = span > 0 ? (sim.state().time - window_sim0_) / span : 0.0;
    t.tick_p50_ms = quantile(tick_ms_, window_n_, 0.5);
    t.tick_p99_ms = quantile(tick_ms_, window_n_, 0.99);
    t.tick_max_ms = quantile(tick_ms_, window_n_, 1.0);
    t.jitter_ms = window_n_ > 1 ? quantile(interval_ms_, window_n_, 0.99) - quantile(interval_ms_, window_n_, 0.5) : 0.0;
  }
  t.run_tick_p50_ms = hist_quantile(run_hist_, 0.5);
  t.run_tick_p99_ms = hist_quantile(run_hist_, 0.99);
  t.run_tick_max_ms = run_max_ms_;
  t.target_factor = factor();
  t.overruns = overruns_;
  t.reanchors = reanchors_;
  t.slow_motion = lagging_;
  t.publish_ms = publish_n_ ? publish_acc_ / publish_n_ : 0.0;
  for (int i = 0; i < kStageCount; ++i) t.stage_ms[i] = stage_samples_ ? stage_acc_[i] / stage_samples_ : 0.0;
  t.commands_applied = runner_.applier().applied();
  t.commands_refused = runner_.applier().refused();
  t.commands_late = runner_.applier().late();
  t.paused = paused();
  t.faulted = faulted();
  if (opt_.log_timing && dticks > 0)
    spdlog::info("physics: tick {} t={:.3f} s, {:.0f} ticks/s, real-time factor {:.3f}{} (target {:.3g}), tick p50 {:.3f} ms p99 {:.3f} ms, "
                 "{} overruns, publish {:.3f} ms",
                 t.ticks, t.sim_time, t.achieved_hz, t.realtime_factor, lagging_ ? " SLOW MOTION" : "", t.target_factor, t.tick_p50_ms,
                 t.tick_p99_ms, t.overruns, t.publish_ms);
  window_start_ = now;
  window_tick0_ = runner_.tick();
  window_sim0_ = sim.state().time;
  window_n_ = 0;
  publish_acc_ = 0.0;
  publish_n_ = 0;
  lagging_ = false;
}

void PhysicsLoop::thread_main() {
  try {
    thread_loop();
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> g(fault_mu_);
    fault_text_ = std::string("internal error on the physics thread at tick ") + std::to_string(runner_.tick()) + ": " + e.what();
    have_fault_state_ = runner_.last_good(fault_state_);
    internal_.store(true, std::memory_order_release);
    faulted_.store(true, std::memory_order_release);
  } catch (...) {
    std::lock_guard<std::mutex> g(fault_mu_);
    fault_text_ = "internal error on the physics thread at tick " + std::to_string(runner_.tick()) + ": unknown exception";
    internal_.store(true, std::memory_order_release);
    faulted_.store(true, std::memory_order_release);
  }
}

void PhysicsLoop::thread_loop() {
  const double dt = runner_.sim().model().dt;
  double anchor_wall = wall_s();
  int64_t anchor_tick = runner_.tick();
  double anchor_factor = factor();
  window_start_ = anchor_wall;
  window_tick0_ = runner_.tick();
  window_sim0_ = runner_.sim().state().time;
  StageTimer stage_timer(stage_acc_);
  while (!stop_.load(std::memory_order_acquire)) {
    if (reset_requested_.exchange(false, std::memory_order_acq_rel)) {
      runner_.reset();
      {
        std::lock_guard<std::mutex> g(fault_mu_);
        fault_text_.clear();
        have_fault_state_ = false;
      }
      tick_.store(0, std::memory_order_release);
      run_hist_.fill(0);
      run_max_ms_ = 0.0;
      faulted_.store(false, std::memory_order_release);
      unread_.clear();
      publish();
      anchor_wall = wall_s();
      anchor_tick = 0;
    }
    if (load_step_.load(std::memory_order_acquire) == 1) {
      do_load();
      load_step_.store(2, std::memory_order_release);
      anchor_wall = wall_s();
      anchor_tick = runner_.tick();
    }
    const bool stepping = step_requests_.load(std::memory_order_acquire) > 0;
    const bool at_stop = opt_.stop_at_tick >= 0 && runner_.tick() >= opt_.stop_at_tick;
    if (at_stop && !paused()) pause();
    if ((paused() && !stepping) || faulted()) {
      runner_.finish_hashes();  // idle: a spread hash under way is completed now (a crash then keeps it)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      anchor_wall = wall_s();  // resume in step with the clock from here
      anchor_tick = runner_.tick();
      update_window(wall_s(), false);
      continue;
    }
    if (stepping) step_requests_.fetch_sub(1, std::memory_order_acq_rel);
    const double f = factor();
    if (f != anchor_factor) {  // a new slow-motion factor re-anchors (no jump)
      anchor_wall = wall_s();
      anchor_tick = runner_.tick();
      anchor_factor = f;
    }
    const double start = wall_s();
    if (last_tick_start_ >= 0 && window_n_ < kWindow) interval_ms_[window_n_] = static_cast<float>((start - last_tick_start_) * 1e3);
    last_tick_start_ = start;
    const bool sample = (runner_.tick() & 31) == 0;
    if (sample) ++stage_samples_;
    const bool ok = runner_.step(sample ? &stage_timer : nullptr);
    const double done = wall_s();
    const double period = dt / f;
    const double tick_ms = (done - start) * 1e3;
    if (window_n_ < kWindow) tick_ms_[window_n_++] = static_cast<float>(tick_ms);
    ++run_hist_[static_cast<int>(std::min(tick_ms * 100.0, kRunBins - 1.0))];  // clamped before the cast (a tick held for hours)
    run_max_ms_ = std::max(run_max_ms_, tick_ms);
    if (done - start > period) ++overruns_;
    tick_.store(runner_.tick(), std::memory_order_release);
    if (!ok) {  // the fault path may allocate: the physics stops here
      std::lock_guard<std::mutex> g(fault_mu_);
      fault_text_ = runner_.fault_text();
      have_fault_state_ = runner_.last_good(fault_state_);
      faulted_.store(true, std::memory_order_release);
    }
    publish();
    update_window(wall_s(), false);
    if (opt_.as_fast_as_possible || paused()) continue;
    const double due = anchor_wall + (runner_.tick() - anchor_tick) * period;
    const double now = wall_s();
    if (now > due + opt_.max_lag) {
      // heavier than real time at this factor: run on in slow motion from here, never catch up
      anchor_wall = now;
      anchor_tick = runner_.tick();
      ++reanchors_;
      lagging_ = true;
    } else if (due > now) {
      std::this_thread::sleep_until(Clock::time_point(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(due))));
    } else if (now > due + 2 * period) {
      lagging_ = true;
    }
  }
  update_window(wall_s(), true);
}

}  // namespace ps
