// The filling's live side (between ticks): FillRate / FillTo commands, its read-out, and the
// walk of every mutable field (save / restore / hash, engine/util/state_io.h).
#include <cstdio>

#include "engine/tools/filling.h"
#include "engine/util/error.h"

namespace ps {

bool FillingTool::apply(const Command& c, const Model& m, const State&, CommandRefusal& why) {
  if (c.kind != CommandKind::FillRate && c.kind != CommandKind::FillTo) {
    why.set("not a filling command");
    return false;
  }
  if (c.component < 0 || c.component >= static_cast<int>(m.components.size())) {
    char b[80];
    std::snprintf(b, sizeof b, "component index %d out of range", c.component);
    why.set(b);
    return false;
  }
  const std::string& name = m.components[c.component].name;
  try {
    if (c.kind == CommandKind::FillRate) set_rate(name, c.value);
    else fill_to(name, c.value, c.duration);
  } catch (const InputError& e) {
    why.set(e.what());
    return false;
  }
  return true;
}

void FillingTool::serialize(StateIO& io) {
  // live commands add schedule segments (outside the step), so the lists are walked with their
  // lengths; restore rebuilds them
  for (Organ& o : organs_) {
    uint64_t nr = o.raw.size();
    io.pod(nr);
    if (!io.saving()) o.raw.resize(nr);
    for (Raw& r : o.raw) {
      io.pod(r.kind);
      io.pod(r.value);
      io.pod(r.t0);
      io.pod(r.t1);
      io.string(r.field);
      io.pod(r.line);
      io.pod(r.live);
    }
    uint64_t ns = o.seg.size();
    io.pod(ns);
    if (!io.saving()) o.seg.resize(ns);
    for (Segment& g : o.seg) {
      io.pod(g.t0);
      io.pod(g.t1);
      io.pod(g.v0);
      io.pod(g.slope);
    }
    uint64_t cur = o.cursor;
    io.pod(cur);
    o.cursor = static_cast<size_t>(cur);
    io.pod(o.current);
  }
  io.pod(now_);
  io.strings(reports_);
}

void FillingTool::readout(ToolReadout& r, const Model&, const State&) const {
  r.kind = ToolReadout::Filling;
  std::snprintf(r.name.data(), r.name.size(), "filling");
  r.value = organs_.empty() ? 0.0 : organs_.front().current;
}

}  // namespace ps
