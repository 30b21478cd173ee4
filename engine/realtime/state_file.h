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
};

void write_state_file(const std::string& path, const SavedState& s);  // atomic; throws on I/O error
SavedState read_state_file(const std::string& path);                  // InputError file:line
SavedState parse_state_text(const std::string& text, const std::string& file);  // the same from memory
// state_hash of bytes (the same FNV-1a as Simulation::hash)
uint64_t saved_state_hash(const std::vector<uint8_t>& bytes);

}  // namespace ps
