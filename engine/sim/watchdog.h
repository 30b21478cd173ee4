// Watchdog for long and stressed runs (`prostatesim stress`, the soak benchmark): after each tick
// it checks what the step's own check (NaN/Inf, speed, excursion; State::fault) does not:
//   - energy growth: kinetic energy above what anything in the scene can inject
//     (0.5 * total mass * max_speed^2), or the fastest particle above max_speed;
//   - volume drift: a volume-constrained organ off its target volume by more than volume_drift;
//   - a particle leaving the scene: farther than leave_margin outside the rest bounding box.
// Runs between ticks on the caller's thread; it allocates only in the constructor.
#pragma once
#include <string>

#include "engine/model/model.h"
#include "engine/state/state.h"

namespace ps {

struct WatchLimits {
  double max_speed = 10.0;      // nothing in a surgical scene moves faster (needle clamp 3 m/s) [m/s]
  double volume_drift = 0.05;   // |V - V_target| / V_target of a constrained surface [-]
  double leave_margin = 0.0;    // beyond the rest bounding box of all particles [m]; 0: the scene's
                                // (Model::leave_margin, scenario key watchdog.leave_margin_mm, 50 mm)
};

struct WatchFinding {
  bool ok = true;
  std::string what;             // "energy growth" | "volume drift" | "left the scene" | step fault kind
  int particle = -1;            // offending particle, -1 when not particle-specific
  double time = 0.0;            // [s]
  double value = 0.0;           // the offending speed [m/s], drift [-] or distance [m]
  std::string describe(const Model& m) const;  // one line: what, time, particle (component, rest mm)
};

// The worst values the watchdog has seen over a run (the soak's drift figures). Each is the
// maximum over every check() that got this far: a check that stops at a finding leaves the later
// measures of that tick out.
struct WatchPeaks {
  double max_speed = 0.0;        // fastest particle [m/s]
  int fastest = -1;              // its particle
  double max_speed_time = 0.0;   // when [s]
  double max_kinetic = 0.0;      // total kinetic energy [J]
  double max_kinetic_time = 0.0; // [s]
  double max_volume_drift = 0.0; // |V - V_target| / V_target of a constrained surface [-]
  int worst_surface = -1;        // Model::surfaces index
  double max_volume_drift_time = 0.0;  // [s]
  double max_displacement = 0.0; // largest |x - rest| of a free particle [m]
  int farthest = -1;             // its particle
  double min_margin = 1e300;     // smallest distance of a particle inside the "left the scene"
                                 // box (rest bounds + leave_margin) to its faces [m]
  int64_t checks = 0;            // ticks checked
};

class Watchdog {
 public:
  Watchdog(const Model& m, WatchLimits limits = {});
  // After a tick. Returns the first problem found (ok=false) or ok. With `peaks`, also records the
  // worst values seen (allocation-free).
  WatchFinding check(const Model& m, const State& s, WatchPeaks* peaks = nullptr) const;
  const WatchLimits& limits() const { return lim_; }
  // Energy limit: 0.5 * total mass * max_speed^2 [J]
  double max_kinetic() const { return 0.5 * total_mass_ * lim_.max_speed * lim_.max_speed; }

 private:
  WatchLimits lim_;
  double total_mass_ = 0.0;     // [kg]
  Vec3 lo_, hi_;                // rest bounding box widened by leave_margin [m]
};

}  // namespace ps
