// A soak checkpoint on disk (`prostatesim stress --cases soak --checkpoint FILE`, `--resume FILE`):
// the one-hour soak of a default scene takes longer than a working session on this machine's
// shared cores, so it is written every few minutes and can go on later from where it stopped,
// ending bit for bit where a run straight through would (the physics is deterministic).
// Written atomically (engine/util/atomic_file.h): a crash mid-write leaves the previous checkpoint.
//
// Format: text lines "key value...", then two binary blocks:
//   prostatesim-soak 1
//   script <path, or "-" without one>
//   period_ticks <n>            cycles <n>            commands <applied> <refused>
//   spent <wall s> <cpu s>
//   peak_speed <m/s> <particle> <t s>          peak_kinetic <J> <t s>
//   peak_volume_drift <-> <surface> <t s>      peak_displacement <m> <particle>
//   min_margin <m>              checks <n>
//   cycle_drift <max m> <rms m> <particle>     cycle_end_kinetic <first J> <last J>
//   first_cycle_end <n>         then n x 3 doubles (raw)
//   state <bytes>               then a saved state file (engine/realtime/state_file.h)
// One key per line, in this order. Bad input (read_soak_checkpoint): InputError naming file:line.
#pragma once
#include <string>

#include "engine/realtime/soak.h"

namespace ps {

void write_soak_checkpoint(const std::string& path, const SoakCheckpoint& c, const std::string& script);
// `script` receives the script path the checkpoint was taken with ("" for none).
SoakCheckpoint read_soak_checkpoint(const std::string& path, std::string& script);

}  // namespace ps
