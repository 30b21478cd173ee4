// Reports of commands a tool adjusted instead of refusing (a fill rate above the limit clamped, a
// target lengthened to the rate limit, a probe move lengthened to the speed limits): issue 10,
// "refusal reports go to a fixed ring, with no allocation on the physics thread".
//
// A live command is applied on the physics thread between ticks, so the tool writes a plain
// record (a code and the numbers: what was asked, what was used, the limit, in SI units) into a
// fixed ring and never formats text there. Readers turn a record into the sentence a user reads
// (FillingTool::describe, ProbeTool::describe: the CLI, the snapshot's events, the tests).
//
// The ring holds the latest kCapacity records (the oldest overwritten, counted in dropped()). It
// is part of the tool's saved state (every slot, so a save has the same size whatever was
// reported: a save between ticks reuses its buffer and does not allocate).
#pragma once
#include <array>
#include <cstdint>

#include "engine/util/state_io.h"

namespace ps {

enum class ToolReportCode : uint8_t {
  FillRateClamped,     // a: rate asked [m^3/s], b: the limit [m^3/s], c: rate used [m^3/s]
  FillStops,           // a: volume where the segment stops [m^3], b: time it stops [s]
  FillTargetClamped,   // a: target asked [m^3], b: target used [m^3]
  FillLengthened,      // a: target [m^3], b: duration asked [s], c: duration used [s]
  ProbeMoveLengthened, // a: duration asked [s], b: duration used [s], c: max speed [m/s],
                       // d: max angular speed [rad/s]
};

struct ToolReport {
  ToolReportCode code = ToolReportCode::FillRateClamped;
  uint8_t live = 0;    // 1: a live command (time = when it was applied); 0: a scenario entry
  int16_t organ = -1;  // filling: index of the organ in the tool; -1 otherwise
  int32_t line = 0;    // scenario line of the entry (0 for live commands)
  int32_t entry = -1;  // index of the entry in the scenario's list (schedule, moves); -1 live
  double time = 0.0;   // start of the commanded segment or move [s]
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;  // numbers by code (above)
};

class ToolReportRing {
 public:
  static constexpr int kCapacity = 64;
  void push(const ToolReport& r) {  // no allocation
    buf_[static_cast<size_t>(total_ % kCapacity)] = r;
    ++total_;
  }
  int64_t total() const { return total_; }
  int size() const { return static_cast<int>(total_ < kCapacity ? total_ : kCapacity); }
  int64_t dropped() const { return total_ - size(); }
  bool empty() const { return total_ == 0; }
  // the record number k (0 = the first ever pushed); only dropped() <= k < total() are held
  const ToolReport& record(int64_t k) const { return buf_[static_cast<size_t>(k % kCapacity)]; }
  // the i-th oldest record still held (0 <= i < size())
  const ToolReport& at(int i) const { return record(dropped() + i); }
  void clear() { total_ = 0; }

  // save / restore / hash (engine/util/state_io.h): every slot, field by field (no padding)
  void serialize(StateIO& io) {
    io.pod(total_);
    for (ToolReport& r : buf_) {
      io.pod(r.code);
      io.pod(r.live);
      io.pod(r.organ);
      io.pod(r.line);
      io.pod(r.entry);
      io.pod(r.time);
      io.pod(r.a);
      io.pod(r.b);
      io.pod(r.c);
      io.pod(r.d);
    }
  }

 private:
  std::array<ToolReport, kCapacity> buf_{};
  int64_t total_ = 0;
};

}  // namespace ps
