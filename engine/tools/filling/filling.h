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
#include "engine/tools/tool_reports.h"

namespace ps {

inline constexpr double kDefaultMaxFillRate = 5e-6;   // [m^3/s] = 5 ml/s
inline constexpr double kMinVolumeFraction = 0.1;     // target >= 0.1 x rest volume
inline constexpr double kMaxVolumeFactor = 10.0;      // target <= 10 x rest volume

struct ToolKind;  // engine/tools/tool_kind.h

class FillingTool final : public Tool {
 public:
  // its entry in the instrument registry (filling_kind.cpp, engine/tools/tool_kind.h)
  static const ToolKind& kind();
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
  // the clamps since `cursor` as snapshot events (kSnapshotEventAdjusted, text formatted here,
  // on the reader's side of the ring)
  int64_t events_since(int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out, size_t max_size) const override;

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
  // Clamps applied to scripted entries and live commands, as records (no text: a live command
  // writes one on the physics thread without allocating; tool_reports.h).
  const ToolReportRing& report_ring() const { return reports_; }
  // The records still held as sentences, oldest first (reader side: allocates), e.g.
  // "fill.yaml:12: filling.schedule[0]: fill rate 5000 ml/s exceeds the limit 5 ml/s; clamped to
  // 5 ml/s" or "t=0.02 s: live filling command (bladder): stops at 1000 ml (t=0.3 s) to stay
  // within 0.1x..10x the rest volume". A first line says how many older ones were dropped.
  std::vector<std::string> reports() const;
  // One record as text into out[n] (NUL-terminated, truncated to fit; no allocation). brief: no
  // "where" prefix (the snapshot event carries the time), for SnapshotEvent::text.
  void describe(const ToolReport& r, char* out, size_t n, bool brief = false) const;

 private:
  struct Raw {                     // a segment as commanded
    FillSpec::Kind kind;
    double value;                  // Rate [m^3/s], Target [m^3] (factors resolved)
    double t0, t1;                 // [s]; t1 may be +inf for a live rate
    int entry;                     // index in the scenario's filling.schedule, -1 for live commands
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
    double base = 0.0;             // target before the first segment of raw [m^3]: the rest
                                   // volume, or where the segments dropped by compact() left it
    size_t slots = 0;              // fixed length of raw and seg (scripted entries + kLiveSegments)
    std::vector<Raw> raw;          // sorted by t0
    std::vector<Segment> seg;      // resolved, sorted by t0
    size_t cursor = 0;             // segment in force (time only moves forward)
    double current = 0.0;          // target at now_ [m^3]
  };
  // Room for live segments beyond the scripted ones. compact() runs before each live command, so
  // at most two are held (the one in force and the new one): the lists never grow past their
  // construction size, and the saved state keeps its length (a save or hash between ticks reuses
  // its buffer: no allocation on the physics thread, issue 10).
  static constexpr size_t kLiveSegments = 4;
  void resolve(Organ& o, bool constructing);
  // Drops the segments that have ended (every one that started before the last one started at or
  // before now_), keeping the volume they reached in Organ::base: the same targets to the bit.
  void compact(Organ& o);
  // The position where a live segment starting now_ goes in o.raw (after compact()).
  size_t insert_live(Organ& o, const Raw& r);
  void report(const Organ& o, const Raw& r, ToolReportCode code, double a, double b, double c = 0.0);
  Organ& organ(const std::string& component, const char* field);
  static double value_at(const Organ& o, size_t& cursor, double t);

  double max_rate_ = kDefaultMaxFillRate;
  std::vector<Organ> organs_;
  double now_ = 0.0;
  std::string file_;
  ToolReportRing reports_;
};

// The filling of a scenario (nullptr when it has no filling: section).
std::unique_ptr<FillingTool> make_filling_tool(const ScenarioSpec& spec, const Model& model);

}  // namespace ps
