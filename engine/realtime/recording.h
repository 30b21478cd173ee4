// Bit-exact record and replay (Box2D's recordings): a recording is the scenario's identity (name,
// content hash, dt, substeps, format and program version) and every command as applied, with the
// tick it was applied at and the tool it went to. Replaying the same (tick, command) pairs on the
// same scenario gives the same bits (tests/engine/realtime/record_replay_test.cpp).
//
// File format (text, one record a line, doubles printed with 17 significant digits so they read
// back exactly):
//   prostatesim-recording 1
//   program 0.1
//   scenario <name>
//   scenario_hash <16 hex digits, FNV-1a of the scenario file>
//   dt <s>
//   substeps <n>
//   c <tick> <kind> <tool> <item> <component> <col> <row> <insertion> <offset x y z> <roll> <tilt>
//     <yaw> <duration> <value> <pos x y z> <dir x y z>            (one line per command)
//   end <ticks> <state hash, 16 hex digits>                       (written when the run ends)
// A recording cut short by a crash has no `end` line; replay then runs to its last command.
//
// The file is FILE.part while recording and renamed to FILE at the end of the run.
// RecordingWriter is the CommandObserver of a live run: the physics thread hands it each applied
// command through a lock-free ring (no I/O, no allocation on the physics thread); a writer thread
// writes them and flushes at least every kFlushSeconds, so a crash loses at most the last second.
// Bad input (parse_recording_*): InputError naming file:line (unknown command, wrong field count,
// ticks going backwards, another scenario or format version); the CLI exits 2.
#pragma once
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "engine/realtime/command.h"
#include "engine/realtime/command_apply.h"
#include "engine/realtime/command_queue.h"

namespace ps {

inline constexpr int kRecordingVersion = 1;
inline constexpr const char* kProgramVersion = "0.1";
inline constexpr double kFlushSeconds = 0.5;

struct RecordingHeader {
  std::string scenario;
  uint64_t scenario_hash = 0;
  double dt = 0.0;
  int substeps = 0;
};

struct Recording {
  std::string file;
  RecordingHeader header;
  int header_line_hash = 0;        // line of scenario_hash (for the mismatch error)
  std::vector<Command> commands;   // non-decreasing ticks
  bool complete = false;           // has an `end` line
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

class RecordingWriter final : public CommandObserver {
 public:
  // Creates (truncates) the file and writes the header; throws InputError when it cannot.
  RecordingWriter(const std::string& path, const RecordingHeader& header);
  ~RecordingWriter() override;  // finish() if not done
  // physics thread: queue one applied command (lock-free, no allocation)
  void applied(const Command& c) override;
  // Writes what is queued and the end line, closes the file. Call after the physics stopped.
  void finish(int64_t ticks, uint64_t state_hash);
  int64_t dropped() const { return dropped_.load(); }  // ring full: the recording is incomplete
  const std::string& path() const { return path_; }

 private:
  void drain();
  void writer_main();
  std::string path_;
  std::FILE* f_ = nullptr;
  CommandQueue ring_{8192};   // drained every 50 ms
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> dropped_{0};
  std::thread thread_;
};

}  // namespace ps
