// The probe's live side (between ticks): the ProbeMove command, its read-out, and the walk of
// every mutable field (save / restore / hash, engine/util/state_io.h).
#include <algorithm>
#include <cstdio>
#include <numbers>

#include "engine/tools/probe/probe.h"
#include "engine/tools/tool_kind.h"
#include "engine/tools/tool_report_text.h"
#include "engine/util/error.h"

namespace ps {

namespace {
void pose_io(ProbePose& p, StateIO& io) {
  io.pod(p.insertion);
  io.vec(p.offset);
  io.pod(p.roll);
  io.pod(p.tilt);
  io.pod(p.yaw);
}
}  // namespace

bool ProbeTool::apply(const Command& c, const Model&, const State&, CommandRefusal& why) {
  if (c.kind != CommandKind::ProbeMove) {
    why.set("not a probe command");
    return false;
  }
  ProbePose p;
  p.insertion = c.probe.insertion;
  p.offset = Vec3(c.probe.offset[0], c.probe.offset[1], c.probe.offset[2]);
  p.roll = c.probe.roll;
  p.tilt = c.probe.tilt;
  p.yaw = c.probe.yaw;
  // refused before anything changes, with a fixed message: no allocation on the physics thread
  if (const char* bad = check_move(p, c.probe.duration)) {
    why.set(bad);
    return false;
  }
  move_to(p, c.probe.duration);
  return true;
}

void ProbeTool::serialize(StateIO& io) {
  uint64_t next = next_;
  io.pod(next);
  next_ = static_cast<size_t>(next);
  io.pod(active_.t0);
  io.pod(active_.t1);
  pose_io(active_.from, io);
  pose_io(active_.to, io);
  io.pod(now_);
  pose_io(pose_, io);
  io.vec(frame_.pivot);
  io.bytes(frame_.rot.data(), 9 * sizeof(double));
  io.vec(frame_.capsule.back);
  io.vec(frame_.capsule.tip);
  io.vec(frame_.capsule.dir);
  io.pod(frame_.capsule.length);
  io.pod(frame_.capsule.radius);
  io.vec(lo_);
  io.vec(hi_);
  io.array(hit_);
  io.pod(broad_);
  io.array(near_, true);
  io.array(near_mark_);
  io.array(local_);
  io.array(coupled_);
  io.array(touched_);
  io.vec(force_acc_);
  io.vec(torque_acc_);
  io.vec(force_);
  io.vec(torque_);
  io.pod(substeps_acc_);
  io.pod(contacts_);
  io.pod(imposed_);
  io.pod(blocked_);
  io.pod(blocked_substeps_);
  io.pod(penetration_);
  io.pod(penetration_seen_);
  reports_.serialize(io);
}

void ProbeTool::readout(ToolReadout& r, const Model&, const State&) const {
  static const uint8_t kind_index = tool_kind_index(kind());
  r.kind = kind_index;
  r.carries = kCarriesImaging;
  std::snprintf(r.name.data(), r.name.size(), "probe");
  r.tip = frame_.capsule.tip;
  r.axis = frame_.axis();
  r.force = force_.norm();
  r.force_vec = force_;
  r.value = pose_.insertion;
}

void ProbeTool::describe(const ToolReport& r, char* out, size_t n, bool brief) const {
  if (n == 0) return;
  const double deg_s = r.d * 180.0 / std::numbers::pi;
  if (r.code != ToolReportCode::ProbeMoveLengthened) {
    std::snprintf(out, n, "probe: report code %d", static_cast<int>(r.code));
  } else if (brief) {
    std::snprintf(out, n, "probe %s lengthened from %.3g s to %.3g s (limits %.3g mm/s, %.3g deg/s)",
                  r.live ? "command" : "move", r.a, r.b, r.c * 1e3, deg_s);
  } else if (r.live) {
    std::snprintf(out, n,
                  "t=%.4g s: probe command lengthened from %.3g s to %.3g s to respect the speed limits (%.3g mm/s, "
                  "%.3g deg/s)",
                  r.time, r.a, r.b, r.c * 1e3, deg_s);
  } else {
    std::snprintf(out, n, "%s:%d: probe move lengthened from %.3g s to %.3g s to respect the speed limits (%.3g mm/s, %.3g deg/s)",
                  spec_.loc.file.c_str(), r.line, r.a, r.b, r.c * 1e3, deg_s);
  }
}

std::vector<std::string> ProbeTool::reports() const {
  return report_lines(reports_, "probe", [this](const ToolReport& r, char* b, size_t n, bool brief) { describe(r, b, n, brief); });
}

int64_t ProbeTool::events_since(int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out, size_t max_size) const {
  return report_events(reports_, cursor, tool_index, out, max_size,
                       [this](const ToolReport& r, char* b, size_t n, bool brief) { describe(r, b, n, brief); });
}

}  // namespace ps
