// Organ filling (paper §3.3, §5.3; issue 5): the bladder's or rectum's target volume changes
// over time and the engine's exact volume projection (engine/step/volume.cpp) holds the organ's
// closed surface at State::target_volume to round-off every substep. The organ's material must
// be incompressible (that is what makes its surface volume-constrained).
//
// A schedule entry is one linear segment of the target over [t0, t1]: a rate [m^3/s], an
// absolute target [m^3] or a factor of the rest volume reached at t1. The segment that starts
// last takes over (the one running stops at the volume it reached); live commands (set_rate,
// fill_to, between ticks) start at the end of the last substep and take over the same way;
// scripted segments that start later still take over when they start.
//
// Limits (documented, checked):
//  - |dV/dt| <= max_rate (default kDefaultMaxFillRate = 5 ml/s = 300 ml/min). Clinical
//    retrograde bladder filling (cystometry) runs at 10-100 ml/min and "fast" filling above
//    100 ml/min (~1.7 ml/s); natural diuresis is ~1-2 ml/min. 5 ml/s is ~3x the fastest clinical
//    filling; a faster rate is clamped (rates) or the segment lengthened (targets) and reported.
//    A scene may raise the limit (filling.max_rate_ml_s) for short tests, and must say so.
//  - target > 0 (InputError), and kept within [kMinVolumeFraction, kMaxVolumeFactor] x the rest
//    volume: a scripted target or rate leaving that range is an InputError naming the entry; a
//    live command is clamped there and reported. Outside it the membrane's shape memory
//    (calibrated for moderate strain) no longer describes an organ.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "engine/spec/scenario_spec.h"
#include "engine/step/simulation.h"

namespace ps {

inline constexpr double kDefaultMaxFillRate = 5e-6;   // [m^3/s] = 5 ml/s
inline constexpr double kMinVolumeFraction = 0.1;     // target >= 0.1 x rest volume
inline constexpr double kMaxVolumeFactor = 10.0;      // target <= 10 x rest volume

class FillingTool final : public Tool {
 public:
  // Throws InputError naming the schedule entry for an unknown or non-volume-constrained
  // component, target <= 0, a volume leaving the allowed range or a rate that is not finite.
  FillingTool(const FillingSpec& spec, const Model& model);

  const char* name() const override { return "filling"; }
  void boundary_conditions(const Model& m, State& s, double dt) override;
  // live use (filling_live.cpp): FillRate, FillTo; every mutable field walked by serialize()
  bool apply(const Command& c, const Model& m, const State& s, CommandRefusal& why) override;
  bool accepts(CommandKind k) const override { return k == CommandKind::FillRate || k == CommandKind::FillTo; }
  void serialize(StateIO& io) override;
  void readout(ToolReadout& r, const Model& m, const State& s) const override;

  // --- live commands (between ticks, on the physics thread; from another thread push a Command
  // through engine/realtime/command_queue.h, applied by engine/realtime/command_apply.h) ---
  // Constant rate [m^3/s] from now until the volume range ends it; returns the rate used.
  double set_rate(const std::string& component, double rate);
  // Linear change to target [m^3] over duration [s]; returns the duration used.
  double fill_to(const std::string& component, double target, double duration);

  // Target volume of a filled organ at the end of the last substep [m^3]; throws InputError for
  // a component that is not filled.
  double target_volume(const std::string& component) const;
  double max_rate() const { return max_rate_; }
  const std::vector<std::string>& reports() const { return reports_; }

 private:
  struct Raw {                     // a segment as commanded
    FillSpec::Kind kind;
    double value;                  // Rate [m^3/s], Target [m^3] (factors resolved)
    double t0, t1;                 // [s]; t1 may be +inf for a live rate
    std::string field;             // scenario key for messages ("filling.schedule[2]")
    int line;                      // scenario line, 0 for live commands
    bool live;                     // a live command (clamped and reported, never an error)
  };
  struct Segment {                 // resolved: V(t) = v0 + slope (min(t, t1) - t0), t >= t0
    double t0, t1, v0, slope;
  };
  struct Organ {
    int surface = -1;
    std::string name;
    double rest = 0.0;             // [m^3]
    std::vector<Raw> raw;          // sorted by t0
    std::vector<Segment> seg;      // resolved, sorted by t0
    size_t cursor = 0;             // segment in force (time only moves forward)
    double current = 0.0;          // target at now_ [m^3]
  };
  static constexpr size_t kLiveSegments = 256;
  void resolve(Organ& o, bool constructing);
  Organ& organ(const std::string& component, const char* field);
  static double value_at(const Organ& o, size_t& cursor, double t);

  double max_rate_ = kDefaultMaxFillRate;
  std::vector<Organ> organs_;
  double now_ = 0.0;
  std::string file_;
  std::vector<std::string> reports_;
};

// The filling of a scenario (nullptr when it has no filling: section).
std::unique_ptr<FillingTool> make_filling_tool(const ScenarioSpec& spec, const Model& model);

}  // namespace ps
