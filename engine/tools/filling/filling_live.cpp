// The filling's live side (between ticks): FillRate / FillTo commands, its read-out, and the
// walk of every mutable field (save / restore / hash, engine/util/state_io.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "engine/tools/filling/filling.h"
#include "engine/tools/tool_kind.h"
#include "engine/tools/tool_report_text.h"
#include "engine/util/error.h"

namespace ps {

bool FillingTool::apply(const Command& c, const Model& m, const State&, CommandRefusal& why) {
  // every refusal is found here, before the tool changes, with a fixed message: a refused
  // command costs no allocation on the physics thread either (issue 10)
  if (c.kind != CommandKind::FillRate && c.kind != CommandKind::FillTo) {
    why.set("not a filling command");
    return false;
  }
  if (c.fill.component < 0 || c.fill.component >= static_cast<int>(m.components.size())) {
    char b[80];
    std::snprintf(b, sizeof b, "component index %d out of range", c.fill.component);
    why.set(b);
    return false;
  }
  const std::string& name = m.components[c.fill.component].name;
  bool filled = false;
  for (const Organ& o : organs_) filled |= o.name == name;
  if (!filled) {
    char b[120];
    std::snprintf(b, sizeof b, "'%s' is not a filled organ (list it in the filling: section)", name.c_str());
    why.set(b);
    return false;
  }
  if (c.kind == CommandKind::FillRate) {
    if (!std::isfinite(c.fill.value)) {
      why.set("filling.set_rate.rate: rate must be finite");
      return false;
    }
    set_rate(name, c.fill.value);
    return true;
  }
  if (!(c.fill.value > 0.0) || !std::isfinite(c.fill.value)) {
    why.set("filling.fill_to.target: a target volume must be > 0");
    return false;
  }
  if (!(c.fill.duration >= 0.0) || !std::isfinite(c.fill.duration)) {
    why.set("filling.fill_to.duration: must be >= 0");
    return false;
  }
  fill_to(name, c.fill.value, c.fill.duration);
  return true;
}

void FillingTool::serialize(StateIO& io) {
  // live commands change the schedule (outside the step): each list is walked as its length and
  // all its fixed slots (Organ::slots; unused ones as zeros), so a save has the same length
  // whatever was commanded and a save or hash between ticks reuses its buffer; restore rebuilds
  // the lists from the lengths
  for (Organ& o : organs_) {
    uint64_t nr = o.raw.size();
    io.pod(nr);
    if (nr > o.slots) throw std::runtime_error("StateIO: filling schedule longer than its slots");
    if (!io.saving()) o.raw.resize(nr);
    for (size_t i = 0; i < o.slots; ++i) {
      Raw spare{FillSpec::Rate, 0.0, 0.0, 0.0, -1, 0, false};
      Raw& r = i < nr ? o.raw[i] : spare;
      io.pod(r.kind);
      io.pod(r.value);
      io.pod(r.t0);
      io.pod(r.t1);
      io.pod(r.entry);
      io.pod(r.line);
      io.pod(r.live);
    }
    uint64_t ns = o.seg.size();
    io.pod(ns);
    if (ns > o.slots) throw std::runtime_error("StateIO: filling segments longer than their slots");
    if (!io.saving()) o.seg.resize(ns);
    for (size_t i = 0; i < o.slots; ++i) {
      Segment spare{0.0, 0.0, 0.0, 0.0};
      Segment& g = i < ns ? o.seg[i] : spare;
      io.pod(g.t0);
      io.pod(g.t1);
      io.pod(g.v0);
      io.pod(g.slope);
    }
    uint64_t cur = o.cursor;
    io.pod(cur);
    o.cursor = static_cast<size_t>(cur);
    io.pod(o.current);
    io.pod(o.base);
  }
  io.pod(now_);
  reports_.serialize(io);
}

void FillingTool::readout(ToolReadout& r, const Model&, const State&) const {
  static const uint8_t kind_index = tool_kind_index(kind());
  r.kind = kind_index;
  r.carries = kCarriesVolume;
  std::snprintf(r.name.data(), r.name.size(), "filling");
  r.value = organs_.empty() ? 0.0 : organs_.front().current;
}

void FillingTool::describe(const ToolReport& r, char* out, size_t n, bool brief) const {
  constexpr double kMl = 1e-6;  // m^3 -> ml
  if (n == 0) return;
  const char* organ = r.organ >= 0 && r.organ < static_cast<int>(organs_.size()) ? organs_[r.organ].name.c_str() : "?";
  int k = 0;
  if (brief) k = std::snprintf(out, n, "%s: ", organ);
  else if (r.live) k = std::snprintf(out, n, "t=%.4g s: live filling command (%s): ", r.time, organ);
  else k = std::snprintf(out, n, "%s:%d: filling.schedule[%d]: ", file_.c_str(), r.line, r.entry);
  if (k < 0 || static_cast<size_t>(k) >= n) return;
  char* p = out + k;
  const size_t left = n - static_cast<size_t>(k);
  switch (r.code) {
    case ToolReportCode::FillRateClamped:
      std::snprintf(p, left, "fill rate %.4g ml/s exceeds the limit %.4g ml/s; clamped to %.4g ml/s", r.a / kMl, r.b / kMl,
                    r.c / kMl);
      break;
    case ToolReportCode::FillStops:
      std::snprintf(p, left, "stops at %.4g ml (t=%.4g s) to stay within 0.1x..10x the rest volume", r.a / kMl, r.b);
      break;
    case ToolReportCode::FillTargetClamped:
      std::snprintf(p, left, "target %.4g ml clamped to %.4g ml (0.1x..10x the rest volume)", r.a / kMl, r.b / kMl);
      break;
    case ToolReportCode::FillLengthened:
      std::snprintf(p, left, "reaching %.4g ml in %.4g s exceeds the rate limit %.4g ml/s; lengthened to %.4g s", r.a / kMl,
                    r.b, max_rate_ / kMl, r.c);
      break;
    default:
      std::snprintf(p, left, "report code %d", static_cast<int>(r.code));
  }
}

std::vector<std::string> FillingTool::reports() const {
  return report_lines(reports_, "filling", [this](const ToolReport& r, char* b, size_t n, bool brief) { describe(r, b, n, brief); });
}

int64_t FillingTool::events_since(int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out, size_t max_size) const {
  return report_events(reports_, cursor, tool_index, out, max_size,
                       [this](const ToolReport& r, char* b, size_t n, bool brief) { describe(r, b, n, brief); });
}

}  // namespace ps
