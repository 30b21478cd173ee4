// A saved simulation state on disk: what `run` / `replay` / the window write when the physics
// faults (the last good state, issue 14 "recovery"), readable back into a simulation built from
// the same scenario file. Written atomically (engine/util/atomic_file.h): a crash mid-write
// leaves no half file.
//
// Format: text header lines, then the raw bytes of Simulation::save():
//   prostatesim-state 1
//   program 0.1
//   scenario <name>
//   scenario_hash <16 hex digits>      (FNV-1a of the scenario file, as in recordings)
//   tick <ticks completed>
//   time <s, 17 significant digits>
//   state_hash <16 hex digits>         (FNV-1a of the bytes: Simulation::hash() after restore)
//   fault <one line: what stopped the physics, or "none">
//   bytes <n>
//   <n raw bytes>
// Bad input (read_state_file): InputError naming file:line; the CLI exits 2.
// `tick` is the number of ticks completed: the state is the one a run has after that many ticks,
// before the commands stamped with that tick are applied (TickRunner::load_state goes on from
// there: `replay --duration tick*dt --hash` of the same inputs prints the file's state_hash).
// Loading (TickRunner::load_state, PhysicsLoop::load_state, `run`/`replay --state FILE`, the
// window's Load state button) first checks that the file was saved from this scenario
// (check_state_matches): another scenario is bad input naming the file, line and field.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace ps {

struct SavedState {
  std::string scenario;
  uint64_t scenario_hash = 0;
  int64_t tick = 0;
  double time = 0.0;               // [s]
  uint64_t state_hash = 0;         // fnv1a of bytes
  std::string fault = "none";      // why it was saved (one line)
  std::vector<uint8_t> bytes;      // Simulation::save()
  std::string file;                // where it was read from (messages; "" when made in memory)
};

void write_state_file(const std::string& path, const SavedState& s);  // atomic; throws on I/O error
std::string state_file_text(const SavedState& s);                     // the same file's content
SavedState read_state_file(const std::string& path);                  // InputError file:line
SavedState parse_state_text(const std::string& text, const std::string& file);  // the same from memory
// state_hash of bytes (the same FNV-1a as Simulation::hash)
uint64_t saved_state_hash(const std::vector<uint8_t>& bytes);
// InputError (file:line:field) unless `s` was saved from the scenario `name` with content hash
// `scenario_hash` (the file's bytes, as in recordings: an edited scenario file does not match).
void check_state_matches(const SavedState& s, const std::string& name, uint64_t scenario_hash);

}  // namespace ps
