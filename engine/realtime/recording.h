// Bit-exact record and replay (Box2D's recordings): a recording is the scenario's identity (name,
// content hash, dt, substeps, format and program version) and every command as applied, with the
// tick it was applied at and the tool it went to. Replaying the same (tick, command) pairs on the
// same scenario gives the same bits (tests/engine/realtime/record_replay_test.cpp).
//
// File format (text, one record a line, doubles printed with 17 significant digits so they read
// back exactly):
//   prostatesim-recording 2                                       (1: no hash_every / h lines)
//   program 0.1
//   scenario <name>
//   scenario_hash <16 hex digits, FNV-1a of the scenario file>
//   dt <s>
//   substeps <n>
//   hash_every <n>                                                (ticks between h lines, 0: none)
//   c <tick> <kind> <tool> <item> <component> <col> <row> <insertion> <offset x y z> <roll> <tilt>
//     <yaw> <duration> <value> <pos x y z> <dir x y z>            (one line per command)
//   h <ticks> <state hash, 16 hex digits>                         (after every hash_every-th tick)
//   fault <tick>                                                  (the physics faulted running it)
//   end <ticks> <state hash, 16 hex digits>                       (written when the run ends)
// A recording cut short by a crash has no `end` line; replay then runs to its last command or
// hash, whichever is later. Replay checks every `h` line (HashVerifier) and names the file, line
// and tick of the first one that differs: where a replay stopped being bit-exact.
//
// The file is FILE.part while recording and renamed to FILE at the end of the run.
// RecordingWriter is the CommandObserver and HashObserver of a live run: the physics thread hands
// it each applied command and periodic hash through one lock-free ring (no I/O, no allocation on
// the physics thread, so lines keep the physics order); a writer thread writes them and flushes
// (fflush: into the OS, which keeps them if the process dies) at least every kFlushSeconds, so a
// crash loses at most the last second and leaves FILE.part, which replay reads.
// Bad input (parse_recording_*): InputError naming file:line (unknown command, wrong field count,
// ticks going backwards, another scenario or format version); the CLI exits 2.
#pragma once
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "engine/contract/command.h"
#include "engine/realtime/command_apply.h"
#include "engine/realtime/command_queue.h"
#include "engine/realtime/spsc_ring.h"
#include "engine/realtime/tick_runner.h"

namespace ps {

inline constexpr int kRecordingVersion = 2;   // reads 1 and 2
inline constexpr int kDefaultHashEvery = 100;  // ticks between recorded state hashes (0.1 s at 1 kHz)
inline constexpr const char* kProgramVersion = "0.1";
inline constexpr double kFlushSeconds = 0.5;

struct RecordingHeader {
  std::string scenario;
  uint64_t scenario_hash = 0;
  double dt = 0.0;
  int substeps = 0;
  int hash_every = kDefaultHashEvery;  // ticks between `h` lines (0: none)
};

struct RecordedHash {
  int64_t tick = 0;                // ticks completed
  uint64_t hash = 0;
  int line = 0;                    // in the recording file
};

struct Recording {
  std::string file;
  RecordingHeader header;
  int header_line_hash = 0;        // line of scenario_hash (for the mismatch error)
  std::vector<Command> commands;   // non-decreasing ticks
  std::vector<RecordedHash> hashes;   // increasing ticks
  bool complete = false;           // has an `end` line
  int end_line = 0;
  int64_t fault_tick = -1;         // `fault` line: the live run faulted running this tick
  int64_t end_tick = 0;
  uint64_t end_hash = 0;
};

Recording parse_recording_text(const std::string& text, const std::string& file);
Recording parse_recording_file(const std::string& path);
// Throws InputError (file:line) when the recording was made on another scenario or timing.
void check_recording_matches(const Recording& r, const RecordingHeader& scene);

// One command as a recording line (without the newline), and back (false on a malformed line).
std::string format_command_line(const Command& c);

std::string hex16(uint64_t h);

// Checks a replay's periodic hashes against a recording's `h` lines (the TickRunner's
// HashObserver in replay, set with the recording's hash_every).
class HashVerifier final : public HashObserver {
 public:
  explicit HashVerifier(const Recording& r) : rec_(r) {}
  void state_hash(int64_t ticks, uint64_t hash) override;
  int checked() const { return checked_; }
  bool diverged() const { return first_bad_ >= 0; }
  // "FILE:LINE: tick T: replay state hash X, the recording has Y" of the first mismatch
  std::string describe() const;
  int64_t diverged_tick() const { return first_bad_ < 0 ? -1 : rec_.hashes[first_bad_].tick; }

 private:
  const Recording& rec_;
  size_t next_ = 0;
  int checked_ = 0;
  int first_bad_ = -1;
  uint64_t got_ = 0;
};

class RecordingWriter final : public CommandObserver, public HashObserver {
 public:
  // Creates (truncates) the file and writes the header; throws InputError when it cannot.
  RecordingWriter(const std::string& path, const RecordingHeader& header);
  ~RecordingWriter() override;  // finish() if not done
  // physics thread: queue one applied command / periodic hash (lock-free, no allocation)
  void applied(const Command& c) override;
  void state_hash(int64_t ticks, uint64_t hash) override;
  int hash_every() const { return hash_every_; }  // for TickRunner::set_hash_observer
  // Writes what is queued and the end line, closes the file. Call after the physics stopped.
  // fault_tick >= 0: the physics faulted running that tick (a `fault` line; replay then expects
  // the same fault there).
  void finish(int64_t ticks, uint64_t state_hash, int64_t fault_tick = -1);
  int64_t dropped() const { return dropped_.load(); }  // ring full: the recording is incomplete
  const std::string& path() const { return path_; }

 private:
  void drain();
  void writer_main();
  std::string path_;
  struct Entry {
    Command c;
    uint64_t hash = 0;
    bool is_hash = false;         // an `h` line (c.tick = ticks) instead of a command
  };
  std::FILE* f_ = nullptr;
  int hash_every_ = 0;
  SpscRing<Entry> ring_{8192};  // drained every 50 ms
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> dropped_{0};
  std::thread thread_;
};

}  // namespace ps
