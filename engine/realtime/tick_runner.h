// The one place a tick happens for live use, shared by the real-time PhysicsLoop (its own thread,
// wall-clock paced) and the LockstepRunner (no thread, no clock: headless replay, PNG frames,
// tests), so both give the same bits for the same (tick, command) pairs:
//   1. every CommandSource is polled (devices, scripts, a recording), in the order added;
//   2. the queue's commands stamped <= tick are applied (the UI thread's pushes);
//   3. Simulation::tick().
// Applied commands go to the observer (the recorder) stamped with the tick they were applied at.
// Snapshots: fill_snapshot() copies what readers need (engine/contract/snapshot.h).
//
// Recovery (issue 14): a fault (the step's own NaN / speed / excursion check, or the optional
// Watchdog after each tick: energy growth, volume drift, a particle leaving the scene) stops the
// runner; fault_text() names the tick, time, kind and particle. With keep_last_good(true) the
// state before the faulting tick can be had (last_good()), so it can be written to a file
// (engine/realtime/state_file.h), and reset() goes back to the start. It is not saved before
// every tick (a whole state, ~1.2 MB and ~50 us in a default scene, every tick): the runner keeps
// a checkpoint every kCheckpointTicks ticks and the commands applied since, and on a fault
// rebuilds the state before the faulting tick by running on from the checkpoint with the same
// commands: the same bits (the run is deterministic in its (tick, command) pairs; tested), at
// the cost of at most kCheckpointTicks ticks once, after the fault.
// Periodic state hashes: with set_hash_observer(o, n) the runner hands o the full state hash
// after every n-th tick (recordings carry them; replay checks them and names the first tick that
// diverges); the real-time loop spreads each over the ticks after it (spread_hashes), so no tick
// carries the whole ~1.5 ms of it.
// Saved states (engine/realtime/state_file.h): current_state() is the state after tick() ticks,
// before that tick's commands; so is the last good state. load_state() goes on from one: the
// simulation restored, tick() set to its tick, sources seek()ed there, the queue emptied, the
// fault cleared; `replay --duration T` of the same inputs and a load of the state saved at T then
// run on give the same bits.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/realtime/command_apply.h"
#include "engine/realtime/command_queue.h"
#include "engine/contract/snapshot.h"
#include "engine/realtime/state_file.h"
#include "engine/sim/watchdog.h"
#include "engine/step/simulation.h"

namespace ps {

// Something polled once per tick on the physics thread that may apply commands (a device, a
// script, a recording). poll() runs between ticks; it must not block.
class CommandSource {
 public:
  virtual ~CommandSource() = default;
  // Applies this source's commands due before tick `tick` through `apply.apply(c, tick)`.
  virtual void poll(int64_t tick, const Simulation& sim, CommandApplier& apply) = 0;
  // Called after each tick with the simulation (force feedback to a device). Default: nothing.
  virtual void after_tick(int64_t /*tick*/, const Simulation& /*sim*/) {}
  // Back to the start (the loop's reset).
  virtual void rewind() {}
  // The run goes on from tick `tick` (a saved state was loaded: TickRunner::load_state): the
  // commands stamped before it are in that state already. Default: rewind() (a device takes a
  // new reference from where the hand is); a command list skips to its first command >= tick.
  virtual void seek(int64_t /*tick*/) { rewind(); }
};

// Receives the full state hash after every n-th tick (TickRunner::set_hash_observer).
class HashObserver {
 public:
  virtual ~HashObserver() = default;
  virtual void state_hash(int64_t ticks, uint64_t hash) = 0;  // ticks completed
};

class TickRunner {
 public:
  // `sim` must outlive the runner. The initial state is saved for reset().
  explicit TickRunner(Simulation& sim, size_t queue_capacity = 1024);

  void add_source(CommandSource* s) { sources_.push_back(s); }
  CommandQueue& queue() { return queue_; }
  CommandApplier& applier() { return applier_; }
  Simulation& sim() { return sim_; }
  const Simulation& sim() const { return sim_; }

  // Runs one tick (polls, applies, ticks). False when the simulation faulted (it stays stopped).
  bool step(StageProbe* probe = nullptr);
  int64_t tick() const { return tick_; }        // ticks completed
  bool faulted() const { return faulted_; }
  // Back to the state at construction, tick 0, sources rewound, queue emptied, fault cleared.
  void reset();
  // The current state (between ticks) with its tick, time and hash; scenario fields left empty.
  void current_state(SavedState& out);
  // Goes on from a saved state of this scenario (check_state_matches first: this checks only
  // that the bytes fit this simulation). Throws InputError naming st.file and the field at
  // fault ("bytes", "state_hash") with the runner and the simulation unchanged.
  void load_state(const SavedState& st);

  // --- recovery ---
  // Checked after every tick (must outlive the runner; null: none). A finding is a fault.
  void set_watchdog(const Watchdog* w) { watchdog_ = w; }
  // Keep what it takes to give the state before each tick (the last good state when the tick
  // faults): a checkpoint now, then one every kCheckpointTicks ticks, and the applied commands.
  void keep_last_good(bool on);
  // The state before the tick that faulted, or that threw (or the current state when neither).
  // False when keep_last_good is off. Fills bytes, tick, time and the state hash. After a fault
  // this re-runs the ticks since the last checkpoint (and allocates): not on the physics path.
  bool last_good(SavedState& out);
  static constexpr int kCheckpointTicks = 100;
  static constexpr size_t kLogCapacity = 4096;  // commands between checkpoints (more: an early checkpoint)
  // "tick 1234: t=1.234 s: particle 17 (component 'prostate') position or velocity is NaN/Inf"
  // or "tick 1234: watchdog: energy growth at t=..., particle ..." ("" when not faulted)
  const std::string& fault_text() const { return fault_text_; }
  // Test hook (the loop, never the step): before tick `tick` runs, particle `particle`'s
  // position is made NaN (once), so the step's own check faults on it (a simulation fault); with
  // `internal`, a std::logic_error is thrown instead (an internal error: a bug). -1: off.
  void inject_fault(int64_t tick, int particle = 0, bool internal = false) {
    inject_tick_ = tick;
    inject_particle_ = particle;
    inject_internal_ = internal;
  }

  // --- periodic hashes (recordings) ---
  void set_hash_observer(HashObserver* o, int every) {
    hash_observer_ = o;
    hash_every_ = every;
    // sizes the simulation's hash buffer here, not at the first hashed tick (every save has the
    // same length, so later hashes reuse it: no allocation on the physics thread)
    if (o) sim_.hash();
  }
  int hash_every() const { return hash_observer_ ? hash_every_ : 0; }
  // Spread each periodic hash over the ticks after it (the real-time loop): the state is saved
  // at its tick (a copy, ~50 us) and its FNV-1a (~1.5 ms over the ~1.2 MB of a default scene: one
  // byte at a time, a multiply each) is taken a slice per tick over the next hash_every / 2
  // ticks, then handed to the observer with the tick it belongs to. The same hash, later; no
  // tick carries the whole of it. Off (the default): at the tick itself. Sizes the buffer here.
  void spread_hashes(bool on);
  // Completes a spread hash still under way and hands it over (the loop's stop(), before a
  // recording is finished). Between ticks, with the physics thread stopped.
  void finish_hashes();

  // Fills `out` with the current state. keep_events: `out` holds events not yet read (a
  // snapshot the reader skipped), so append to them instead of replacing them. max_events: the
  // most `out.events` holds afterwards; newer events wait for the next call (no allocation when
  // it is the vector's reserved capacity).
  void fill_snapshot(Snapshot& out, bool keep_events = false, bool with_hash = false,
                     size_t max_events = std::numeric_limits<size_t>::max());

 private:
  Simulation& sim_;
  CommandQueue queue_;
  CommandApplier applier_;
  std::vector<CommandSource*> sources_;
  int64_t tick_ = 0;
  bool faulted_ = false;
  std::vector<uint8_t> initial_;
  std::vector<int64_t> event_cursor_;  // per tool
  int64_t refusal_cursor_ = 0;
  uint64_t event_seq_ = 0;             // the last SnapshotEvent::seq given
  const Watchdog* watchdog_ = nullptr;
  bool keep_good_ = false;
  // recovery (keep_last_good): the state after checkpoint_tick_ ticks, before that tick's
  // commands, and every command applied since, stamped with its tick (at most kLogCapacity: a
  // full log takes a checkpoint at the next tick's start; the ticks a rebuild needs are all in it)
  struct CommandLog final : CommandObserver {
    std::vector<Command> cmds;  // capacity reserved: no allocation on the physics thread
    void applied(const Command& c) override {
      if (cmds.size() < cmds.capacity()) cmds.push_back(c);
      else full = true;
    }
    bool full = false;
  };
  std::vector<uint8_t> checkpoint_;
  int64_t checkpoint_tick_ = 0;
  CommandLog log_;
  bool in_step_ = false;  // step() began and did not return (an exception left it mid-tick)
  void take_checkpoint();
  std::string fault_text_;
  int64_t inject_tick_ = -1;
  int inject_particle_ = 0;
  bool inject_internal_ = false;
  HashObserver* hash_observer_ = nullptr;
  int hash_every_ = 0;
  // spread hashing (spread_hashes): the saved state, its tick (-1: none under way), the bytes
  // hashed so far and the running FNV-1a value
  bool spread_ = false;
  std::vector<uint8_t> hash_buf_;
  int64_t hash_tick_ = -1;
  size_t hash_pos_ = 0;
  uint64_t hash_h_ = 0;
  void advance_hash(bool to_end);
};

}  // namespace ps
