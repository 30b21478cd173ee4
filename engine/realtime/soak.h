// Long soak of a scene with its script (issue 14: "at least one hour of simulated time of each
// default scene with its script, with a watchdog on NaN, energy growth, volume drift and particles
// leaving the scene"). The script's commands are replayed in a loop, one cycle every
// period_ticks (the script's duration), through the same TickRunner as `prostatesim run`, and
// the Watchdog (engine/sim/watchdog.h) checks every tick and records the worst values it saw.
// Drift between cycles: the positions at the end of each cycle are compared with those at the end
// of the first (same script phase, so a stable scene repeats itself and a slow creep shows).
// Used by `prostatesim stress --cases soak --soak S` (the one-hour benchmark) and the CI-sized
// soak test. Wall clock and allocation are here, between ticks, never inside the step.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/contract/command.h"
#include "engine/realtime/state_file.h"
#include "engine/realtime/script.h"
#include "engine/sim/scene.h"
#include "engine/sim/watchdog.h"

namespace ps {

// Replays `cmds` (ticks in [0, period)) every `period` ticks: cycle c applies command k at
// cmds[k].tick + c * period. period >= 1 and >= the last command's tick + 1.
class LoopingPlayer final : public CommandSource {
 public:
  LoopingPlayer(std::vector<Command> cmds, int64_t period);
  void poll(int64_t tick, const Simulation&, CommandApplier& apply) override;
  void rewind() override { next_ = 0; cycle_ = 0; }
  // Goes on from tick `tick` (a resumed soak): the commands due before it were applied.
  void seek(int64_t tick) override;
  int64_t period() const { return period_; }

 private:
  std::vector<Command> cmds_;
  int64_t period_;
  size_t next_ = 0;
  int64_t cycle_ = 0;
};

struct SoakCheckpoint;

struct SoakOptions {
  double duration = 3600.0;       // simulated time [s]
  double budget_s = 0.0;          // wall-clock budget [s]; 0: none (reported as a timeout)
  double report_every_s = 60.0;   // wall time between progress callbacks [s]
  double period = 1.0;            // drift comparison period without a script [s]
  WatchLimits limits;
  // A self-excited oscillation: once the scene's own scenario scripts are over (needle keys and
  // gun, probe moves, filling schedule: scripted_motion_end), it repeats itself every cycle (the
  // same phase of the looped script, or nothing moving without one), so the kinetic energy at the
  // end of a cycle grown past ring_factor times that at the first such cycle end, plus
  // ring_floor_j, is an instability feeding itself, not the script. It can stay below the
  // watchdog's energy limit for good (a bladder-wall particle's ~1.5 m/s limit cycle with
  // multirate_inertia 4, docs/performance.md), so it is a finding of its own. ring_factor 0: off.
  double ring_factor = 100.0;  // [-]
  double ring_floor_j = 1e-7;  // [J] the scene's rest threshold (ScenarioSpec::rest_kinetic_energy)
  // A checkpoint (state and the figures so far) is handed to `checkpoint` every
  // checkpoint_every_s of wall time, between ticks, and at the end or the budget's end unless the
  // soak failed (the caller writes it: soak_checkpoint.h).
  double checkpoint_every_s = 300.0;  // [s]
  std::function<void(const SoakCheckpoint&)> checkpoint;
};

struct SoakReport {
  bool held = true;               // no step fault and no watchdog finding
  bool timeout = false;           // the wall budget ran out before `duration`
  std::string fault;              // "tick N: ..." with time and particle
  int64_t ticks = 0, target_ticks = 0;
  double sim_s = 0.0, wall_s = 0.0, cpu_s = 0.0;  // [s]
  int64_t period_ticks = 0;       // one script cycle
  int64_t cycles = 0;             // complete cycles
  int64_t applied = 0, refused = 0;  // script commands
  WatchPeaks peaks;
  WatchLimits limits;             // what the watchdog held the run to
  double kinetic_limit = 0.0;     // the watchdog's energy limit [J]
  // positions at the end of the latest complete cycle against the end of the first [m]
  double cycle_drift_max = 0.0, cycle_drift_rms = 0.0;
  int cycle_drift_particle = -1;
  double cycle_end_kinetic_first = 0.0, cycle_end_kinetic_last = 0.0;  // [J]
  // the self-excitation check's reference: the first cycle end after the scene's own scripts
  // (SoakOptions::ring_factor); cycle 0: not reached yet
  int64_t ring_base_cycle = 0;
  double ring_base_kinetic = 0.0;  // [J]
  // |V - V_target| / V_target of each volume-constrained surface at the end [-] (name, drift)
  std::vector<std::pair<std::string, double>> end_volume_drift;
};

// Where a soak stands between ticks: enough to go on as if it had not stopped. The simulation is
// deterministic, so a soak resumed from a checkpoint ends in the same state, bit for bit, with
// the same figures as one run straight through (tests/engine/realtime/soak_test.cpp).
struct SoakCheckpoint {
  SavedState state;                   // TickRunner::current_state (scenario fields by the caller)
  SoakReport report;                  // the figures so far (wall_s, cpu_s: time spent so far)
  std::vector<Vec3> first_cycle_end;  // positions at the end of cycle 1 (empty before) [m]
};

// Runs `scene` for opt.duration of simulated time (script looped when given), checking every
// tick. progress(report so far) is called every opt.report_every_s of wall time. With `resume`
// (a checkpoint of this scene and script, e.g. read_soak_checkpoint), it goes on from there;
// InputError when its state does not fit the scene.
SoakReport run_soak(Scene& scene, const Script* script, const SoakOptions& opt,
                    const std::function<void(const SoakReport&)>& progress = {},
                    const SoakCheckpoint* resume = nullptr);

// When the scene's own scenario scripts have moved their last (needle script keys and scripted
// gun strokes, probe moves, filling schedule) [s]; 0 when it has none. Live commands and a
// looped soak script are not counted.
double scripted_motion_end(const ScenarioSpec& spec);

// One line of figures: cycles, peaks, drift (units in the text).
std::string soak_figures(const SoakReport& r, const Model& m);

}  // namespace ps
