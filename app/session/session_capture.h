// The session report of `prostatesim run` and `prostatesim replay` (issue 13): a CommandSource
// that applies no command and, after every tick (TickRunner calls after_tick outside
// Simulation::tick, so the physics step stays free of I/O), feeds the needle session metrics
// (engine/metrics/session_metrics.h: no allocation) and the force-versus-depth samples. At the end,
// At up to kPunctureShots punctures or biopsy cores (those of the gland and the cores kept over
// punctures of the organs on the way, the rectal wall or the skin) the positions and instrument
// geometry are copied into buffers sized at construction (no allocation while the draw lists
// stay within the capacity of their first fill) with the probe's pose, so that the report can
// show the ultrasound image at each puncture. At the end, write() puts metrics.json, report.png (app/session/session_report.h) and the CSVs of `insert` into a
// folder, each file atomically.
// The force-depth samples grow with the run (ForceDepthRecorder: amortised vector growth, on the
// physics thread between ticks, never inside the step).
#pragma once
#include <array>
#include <memory>
#include <string>

#include "engine/metrics/score.h"
#include "engine/metrics/session_metrics.h"
#include "engine/realtime/tick_runner.h"
#include "engine/sim/scene.h"
#include "engine/tools/needle/needle_output.h"
#include "engine/ultrasound/scene.h"

namespace ps::app {

class SessionCapture : public CommandSource {
 public:
  // Null when the scene has no needles (nothing to score). Throws InputError when a needle
  // target lies outside the scene.
  static std::unique_ptr<SessionCapture> make(const Scene& scene);

  void poll(int64_t, const Simulation&, CommandApplier&) override {}
  void after_tick(int64_t tick, const Simulation& sim) override;
  void rewind() override;

  // The report at the current state (the loop stopped, or the caller on the physics side).
  SessionReport report(bool faulted) const;
  // Writes metrics.json, report.png, force_depth_<needle>.csv, needle_events.csv, seeds.csv,
  // cores.csv into `dir` (created). Returns the score.
  Score write(const std::string& dir, bool faulted, const std::string& trainee, const std::string& session) const;
  // The force-versus-depth samples so far (one series per needle).
  const ForceDepthRecorder& force_depth() const { return *rec_; }

 private:
  explicit SessionCapture(const Scene& scene);
  static constexpr int kPunctureShots = 4;
  struct Shot {
    Snapshot snap;
    us::ProbeView probe;
    double time = 0.0, depth = 0.0, force = 0.0;
    int needle = -1, component = -1;
    bool core = false;             // a biopsy core (else a puncture)
    bool key = false;              // a core or a puncture of the gland (kept over route punctures)
  };
  const Scene& scene_;
  const NeedleTool& needles_;
  std::array<Shot, kPunctureShots> shots_;
  int shots_used_ = 0;
  int64_t events_seen_ = 0;
  int gland_ = -1;
  std::unique_ptr<SessionMetrics> metrics_;
  std::unique_ptr<ForceDepthRecorder> rec_;
};

}  // namespace ps::app
