// The needle tool's live side (between ticks, on the physics thread): commands from devices,
// scripts and recordings (engine/contract/command.h), the read-out and events a snapshot
// carries, and the walk of every mutable field (save / restore / hash, engine/util/state_io.h).
#include <cmath>
#include <cstdio>
#include <cstring>

#include "engine/anatomy/zones.h"
#include "engine/tools/needle/needle_internal.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/tool_kind.h"
#include "engine/util/error.h"

namespace ps {

namespace {

// The anchors a[0 .. n) walked field by field (count, idx, w, offset, rotational: the bytes of one
// pod() / vec() call each) through one span (StateIO::span): a needle has an anchor per node, and
// the app saves the state for its checkpoints and recording hashes; one bounds check, not five an anchor.
void anchors_io(AffineAnchor* a, size_t n, StateIO& io) {
  constexpr size_t kCount = sizeof(AffineAnchor::count), kIdx = sizeof(AffineAnchor::idx), kW = sizeof(AffineAnchor::w);
  constexpr size_t kOffset = 3 * sizeof(double), kRot = sizeof(AffineAnchor::rotational);
  static_assert(sizeof(Vec3) == kOffset);
  uint8_t* p = io.span((kCount + kIdx + kW + kOffset + kRot) * n);
  const bool save = io.saving();
  auto field = [&](void* f, size_t len) {
    if (save) std::memcpy(p, f, len);
    else std::memcpy(f, p, len);
    p += len;
  };
  for (size_t i = 0; i < n; ++i) {
    field(&a[i].count, kCount);
    field(a[i].idx.data(), kIdx);
    field(a[i].w.data(), kW);
    field(a[i].offset.data(), kOffset);
    field(&a[i].rotational, kRot);
  }
}

void readout_io(NeedleReadout& r, StateIO& io) {
  io.vec(r.tip);
  io.vec(r.direction);
  io.vec(r.velocity);
  io.vec(r.command_tip);
  io.pod(r.plan_depth);
  io.pod(r.depth);
  io.pod(r.contacted);
  io.vec(r.tissue_force);
  io.vec(r.coupling_force);
  io.pod(r.axial_force);
  io.pod(r.axial_force_tick);
  io.pod(r.press_force);
  io.pod(r.cutting_force);
  io.pod(r.friction_force);
  io.pod(r.engaged_nodes);
  io.pod(r.stuck_nodes);
  io.pod(r.phase);
}

// The commanded tip now (so an advance or a new speed starts where the command is).
Vec3 commanded_tip(const NeedleTool::Needle& nd, double t) {
  Vec3 tip, dir, vel;
  needle_command(nd, t, tip, dir, vel);
  return tip - gun_stroke(nd, t) * dir;  // the gun's stroke is added on top again
}

}  // namespace

bool NeedleTool::accepts(CommandKind k) const {
  switch (k) {
    case CommandKind::NeedleAim:
    case CommandKind::NeedleAdvance:
    case CommandKind::NeedleRotate:
    case CommandKind::NeedleRelease:
    case CommandKind::FireGun:
    case CommandKind::DepositSeed:
    case CommandKind::SelectNeedle:
    case CommandKind::SelectHole:
    case CommandKind::NeedleDepth:
      return true;
    default:
      return false;
  }
}

double NeedleTool::hub_roll(int i) const { return needles_.at(i)->hub_roll; }

bool NeedleTool::apply(const Command& c, const Model& m, const State& s, CommandRefusal& why) {
  char msg[120];
  const int i = c.item < 0 ? active_ : c.item;
  if (i < 0 || i >= count()) {
    std::snprintf(msg, sizeof msg, "needle %d does not exist (%d needles)", i, count());
    why.set(msg);
    return false;
  }
  Needle& nd = *needles_[i];
  const double now = s.time;
  switch (c.kind) {
    case CommandKind::NeedleAim: {
      const Vec3 tip(c.needle.pos[0], c.needle.pos[1], c.needle.pos[2]);
      const Vec3 dir(c.needle.dir[0], c.needle.dir[1], c.needle.dir[2]);
      if (!tip.allFinite() || !dir.allFinite() || !(dir.norm() > 1e-9) || !std::isfinite(c.needle.speed)) {
        why.set("needle aim needs a finite tip, speed and a non-zero direction");
        return false;
      }
      if (nd.guided) {  // the guide sets the direction: the tip's depth along it is what counts
        nd.interactive = true;
        nd.cmd_depth = (tip - nd.guide_now.entry).dot(nd.guide_now.direction) - gun_stroke(nd, now);
        nd.cmd_speed = c.needle.speed;
        nd.cmd_t0 = now;
        return true;
      }
      nd.interactive = true;
      nd.cmd_T = tip;
      nd.cmd_d = dir.normalized();
      nd.cmd_V = Vec3::Zero();
      nd.cmd_speed = c.needle.speed;
      nd.cmd_t0 = now;
      return true;
    }
    case CommandKind::NeedleDepth: {
      if (!std::isfinite(c.needle.depth) || !std::isfinite(c.needle.speed)) {
        why.set("needle depth and speed must be finite");
        return false;
      }
      if (c.needle.depth > nd.spec.length) {
        std::snprintf(msg, sizeof msg, "depth %.1f mm is beyond the needle's length %.1f mm", c.needle.depth * 1e3,
                      nd.spec.length * 1e3);
        why.set(msg);
        return false;
      }
      if (nd.guided) {
        nd.interactive = true;
        nd.cmd_depth = c.needle.depth - gun_stroke(nd, now);
      } else {
        const Vec3 d = nd.spec.direction.normalized();
        nd.interactive = true;
        nd.cmd_T = nd.spec.start + (c.needle.depth - gun_stroke(nd, now)) * d;
        nd.cmd_d = d;
        nd.cmd_V = Vec3::Zero();
      }
      nd.cmd_speed = c.needle.speed;
      nd.cmd_t0 = now;
      return true;
    }
    case CommandKind::NeedleAdvance: {
      if (!std::isfinite(c.needle.speed)) {
        why.set("needle advance speed is not finite");
        return false;
      }
      if (nd.guided) {
        nd.cmd_depth = guide_depth(nd, now) - gun_stroke(nd, now);
        nd.interactive = true;
        nd.cmd_speed = c.needle.speed;
        nd.cmd_t0 = now;
        return true;
      }
      if (!nd.interactive) {  // take over from the script where it is now
        Vec3 tip, dir, vel;
        needle_command(nd, now, tip, dir, vel);
        nd.cmd_T = tip - gun_stroke(nd, now) * dir;
        nd.cmd_d = dir;
        nd.cmd_V = Vec3::Zero();
        nd.interactive = true;
      } else {
        nd.cmd_T = commanded_tip(nd, now);
      }
      nd.cmd_speed = c.needle.speed;
      nd.cmd_t0 = now;
      return true;
    }
    case CommandKind::NeedleRotate:
      if (!std::isfinite(c.needle.angle)) {
        why.set("needle rotation is not finite");
        return false;
      }
      nd.hub_roll = c.needle.angle;
      return true;
    case CommandKind::NeedleRelease:
      if (nd.guided && nd.spec.script.empty()) {  // no script to go back to: held where it is in the guide
        nd.cmd_depth = guide_depth(nd, now) - gun_stroke(nd, now);
        nd.cmd_t0 = now;
      } else {
        nd.interactive = false;
      }
      nd.cmd_speed = 0.0;
      return true;
    case CommandKind::FireGun:
      if (!nd.spec.gun) {
        std::snprintf(msg, sizeof msg, "needle '%.60s' has no biopsy gun", nd.spec.name.c_str());
        why.set(msg);
        return false;
      }
      if (!std::isnan(nd.fire_time) && now < nd.fire_time + nd.spec.gun->duration + nd.spec.gun->settle) {
        why.set("the biopsy gun is already firing");
        return false;
      }
      if (nd.guided && !std::isnan(nd.fire_time)) {
        why.set("the biopsy gun has fired: withdraw the needle into the guide to re-arm it");
        return false;
      }
      nd.fire_time = now;
      nd.core.taken = false;
      return true;
    case CommandKind::DepositSeed: {
      bool left = false;
      for (const SeedState& sd : nd.seeds) left |= !sd.deposited;
      if (!left) {
        std::snprintf(msg, sizeof msg, "needle '%.60s' has no seed left", nd.spec.name.c_str());
        why.set(msg);
        return false;
      }
      nd.deposit_request = true;
      return true;
    }
    case CommandKind::SelectNeedle:
      active_ = i;
      return true;
    case CommandKind::SelectHole: {
      if (!probe_) {
        why.set("no probe in the scene: no template to select a hole of");
        return false;
      }
      if (nd.guided) {
        why.set("the needle rides in the probe's biopsy guide, not in the template");
        return false;
      }
      const ProbeSpec& ps = probe_->spec();
      if (c.needle.col < 0 || c.needle.row < 0 || c.needle.col >= ps.template_cols || c.needle.row >= ps.template_rows) {
        std::snprintf(msg, sizeof msg, "template hole (%d, %d) outside the %d x %d grid", c.needle.col, c.needle.row,
                      ps.template_cols, ps.template_rows);
        why.set(msg);
        return false;
      }
      const NeedlePath p = probe_->template_hole(c.needle.col, c.needle.row);
      nd.interactive = true;
      nd.cmd_T = p.entry;
      nd.cmd_d = p.direction.normalized();
      nd.cmd_V = Vec3::Zero();
      nd.cmd_speed = 0.0;
      nd.cmd_t0 = now;
      active_ = i;
      return true;
    }
    default:
      why.set("not a needle command");
      return false;
  }
}

void NeedleTool::serialize(StateIO& io) {
  io.pod(active_);
  for (auto& p : needles_) {
    Needle& nd = *p;
    io.pod(nd.seed_counter);
    io.vec(nd.T);
    io.vec(nd.V);
    io.vec(nd.d);
    io.pod(nd.v_cut);
    io.pod(nd.interactive);
    io.vec(nd.cmd_T);
    io.vec(nd.cmd_d);
    io.vec(nd.cmd_V);
    io.pod(nd.cmd_speed);
    io.pod(nd.cmd_t0);
    io.pod(nd.hub_roll);
    io.pod(nd.deposit_request);
    io.pod(nd.fire_time);
    io.array(nd.tracked, true);
    io.array(nd.next, true);
    io.array(nd.mark);
    io.array(nd.entered);
    io.array(nd.zone_idx);
    io.array(nd.zone_dist);
    io.array(nd.zone_n);
    io.pod(nd.cut_idx);
    io.pod(nd.cut_dist);
    io.pod(nd.cut_n);
    io.pod(nd.press_n);
    io.pod(nd.press_face);
    io.pod(nd.press_idx);
    io.pod(nd.press_w);
    io.pod(nd.press_a);
    io.pod(nd.press_component);
    io.array(nd.face_epoch);
    io.array(nd.face_breached);
    io.pod(nd.press_face_id);
    io.pod(nd.epoch);
    io.pod(nd.lumen);
    io.pod(nd.in_lumen);
    io.pod(nd.exit_a);
    io.vec(nd.exit_point);
    anchors_io(nd.anchors.data(), nd.anchors.size(), io);
    io.array(nd.anchor_c);
    io.array(nd.anchor_csum);
    io.array(nd.stick_scale);
    io.array(nd.stick_scale_used);
    io.array(nd.stuck);
    io.array(nd.reported);
    io.array(nd.pending);
    io.pod(nd.debounce);
    io.pod(nd.contacted);
    io.pod(nd.contact_axial);
    io.pod(nd.peak_force);
    io.pod(nd.bone_touch);
    io.pod(nd.clamping);
    io.pod(nd.phase_blocked);
    readout_io(nd.ro, io);
    io.pod(nd.tick_sum);
    io.pod(nd.tick_n);
    io.pod(nd.stats.tracked);
    io.pod(nd.stats.visited);
    io.pod(nd.stats.plan_checked);
    for (SeedState& sd : nd.seeds) {
      io.pod(sd.depth);
      io.vec(sd.planned);
      io.pod(sd.deposited);
      io.pod(sd.embedded);
      io.pod(sd.time);
      io.vec(sd.at);
      io.vec(sd.current);
      anchors_io(&sd.anchor, 1, io);
    }
    io.pod(nd.deepest);
    CoreState& c = nd.core;
    io.pod(c.taken);
    io.pod(c.time);
    io.array(c.particles, true);
    io.array(c.per_component);
    io.array(c.per_tag);
    io.array(c.tumour_pos, true);
    io.array(c.tumour_half, true);
    io.pod(c.tumour_particles);
    io.pod(c.tumour_length);
    io.pod(c.overflow);
  }
  events_.serialize(io);
  if (budget_) {
    io.array(budget_->g);
    io.array(budget_->touched, true);
    io.pod(budget_->peak);
    io.pod(budget_->after);
    io.pod(budget_->softened);
  }
  io.pod(coupling_stats_.bound);
  io.pod(coupling_stats_.bound_applied);
  io.pod(coupling_stats_.softened_nodes);
  io.pod(coupling_stats_.bound_max);
  io.pod(coupling_stats_.softened_substeps);
  io.strings(warnings_);
  if (!urethra_rest_.empty())  // scenes without a urethra line keep their state's bytes
    for (auto& p : needles_) io.pod(p->near_urethra);
  for (auto& p : needles_) {  // a needle in the guide (free needles keep their state's bytes)
    Needle& nd = *p;
    if (!nd.guided) continue;
    io.vec(nd.guide_now.entry);
    io.vec(nd.guide_now.direction);
    io.vec(nd.guide_prev.entry);
    io.vec(nd.guide_prev.direction);
    io.pod(nd.cmd_depth);
    io.vec(nd.spec.start);
    io.vec(nd.spec.direction);
    io.array(nd.plan_t, true);
    io.array(nd.plan_idx, true);
    io.vec(nd.core.tip);
    io.vec(nd.core.direction);
    io.pod(nd.cores_done_n);
    for (int k = 0; k < nd.cores_done_n; ++k) {
      CoreState& c = nd.cores_done[k];
      io.pod(c.taken);
      io.pod(c.time);
      io.array(c.particles, true);
      io.array(c.per_component);
      io.array(c.per_tag);
      io.pod(c.tumour_particles);
      io.pod(c.tumour_length);
      io.pod(c.overflow);
      io.vec(c.tip);
      io.vec(c.direction);
    }
  }
}

void NeedleTool::readout(ToolReadout& r, const Model&, const State&) const {
  static const uint8_t kind_index = tool_kind_index(kind());
  r.kind = kind_index;
  r.carries = kCarriesInsertion;
  if (needles_.empty()) return;
  const int i = active_ >= 0 && active_ < count() ? active_ : 0;
  const Needle& nd = *needles_[i];
  std::snprintf(r.name.data(), r.name.size(), "%s", nd.spec.name.c_str());
  r.tip = nd.ro.tip;
  r.axis = nd.ro.direction;
  r.depth = nd.ro.depth;
  r.force = nd.ro.axial_force_tick;
  r.force_vec = nd.ro.tissue_force;
  r.value = nd.ro.plan_depth;
  r.active = true;
}

namespace {

// The 12-core site of a core ("right mid medial", the majority tag of each group among its notch's
// prostate particles, as core_site() names it) and whether it held lesion, into out (no
// allocation: the physics thread formats the events it publishes). "" without zone tags.
void core_site_text(const Model& m, const CoreState& core, char* out, size_t n) {
  out[0] = '\0';
  const auto& names = anatomy::kZoneTagNames;
  int count[names.size()] = {};
  bool any = false;
  for (size_t k = 0; k < names.size(); ++k) {
    for (size_t t = 0; t < m.tag_names.size() && t < core.per_tag.size(); ++t)
      if (m.tag_names[t] == names[k]) count[k] = core.per_tag[t];
    any |= count[k] > 0;
  }
  auto pick = [&](int lo, int hi) {
    int best = lo;
    for (int i = lo + 1; i < hi; ++i)
      if (count[i] > count[best]) best = i;
    return best;
  };
  if (!any || count[pick(0, 3)] == 0) {
    std::snprintf(out, n, "outside the gland%s", core.tumour_particles > 0 ? ", lesion" : "");
    return;
  }
  std::snprintf(out, n, "%s %s %s%s", names[pick(3, 5)], names[pick(0, 3)], names[pick(5, 7)], core.tumour_particles > 0 ? ", lesion" : "");
}

}  // namespace

int64_t NeedleTool::events_since(int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out, size_t max_size) const {
  const int64_t total = events_.total();
  const int64_t held = static_cast<int64_t>(events_.size());
  int64_t first = std::max(cursor, total - held);  // older ones were overwritten
  for (int64_t k = first; k < total; ++k) {
    const NeedleEvent& e = events_.at(static_cast<size_t>(held - (total - k)));
    // stick/slip flicker is for plots, not the event list a trainee reads
    if (e.kind == NeedleEventKind::Stick || e.kind == NeedleEventKind::Slip) continue;
    if (out.size() >= max_size) return k;
    SnapshotEvent se;
    se.time = e.time;
    se.tool = tool_index;
    se.kind = static_cast<uint8_t>(e.kind);
    se.position = e.position;
    se.depth = e.depth;
    se.force = e.force;
    const char* who = e.needle >= 0 && e.needle < count() ? needles_[e.needle]->spec.name.c_str() : "needle";
    const char* comp = e.component >= 0 && e.component < static_cast<int>(model_->components.size())
                           ? model_->components[e.component].name.c_str() : "";
    const double shown = std::abs(e.force) < 0.005 ? 0.0 : e.force;  // [N] a first contact's ~0 N, not "-0.00 N"
    std::snprintf(se.text.data(), se.text.size(), "%s: %s%s%s at %.1f mm, %.2f N", who, needle_event_name(e.kind), *comp ? " " : "",
                  comp, e.depth * 1e3, shown);
    // a core of a needle in the guide names its site: "... [right mid medial, lesion]" (the live 12-core map)
    if (e.kind == NeedleEventKind::Core && e.needle >= 0 && e.needle < count() && needles_[e.needle]->guided) {
      const Needle& nd = *needles_[e.needle];
      const CoreState* core = nd.core.taken && nd.core.time == e.time ? &nd.core : nullptr;
      for (int k = 0; k < nd.cores_done_n && !core; ++k)
        if (nd.cores_done[k].time == e.time) core = &nd.cores_done[k];
      if (core) {
        char site[64];
        core_site_text(*model_, *core, site, sizeof site);
        const size_t used = std::strlen(se.text.data());
        std::snprintf(se.text.data() + used, se.text.size() - used, " [%s]", site);
      }
    }
    out.push_back(se);
  }
  return total;
}

}  // namespace ps
