#include "engine/tools/probe/probe.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "engine/mesh/mesh_query.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"

namespace ps {

namespace {

constexpr double kVolumeLoopStop = 1e-6;  // stop alternating once corrections are below 1 um [m]

std::string mm(double metres) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g mm", metres * 1e3);
  return b;
}

ProbePose merge(const ProbePose& from, const ProbeMoveSpec& mv) {
  ProbePose p = from;
  if (mv.insertion) p.insertion = *mv.insertion;
  if (mv.offset) p.offset = *mv.offset;
  if (mv.roll) p.roll = *mv.roll;
  if (mv.tilt) p.tilt = *mv.tilt;
  if (mv.yaw) p.yaw = *mv.yaw;
  return p;
}

bool finite_pose(const ProbePose& p) {
  return std::isfinite(p.insertion) && p.offset.allFinite() && std::isfinite(p.roll) && std::isfinite(p.tilt) &&
         std::isfinite(p.yaw);
}

// Closed surface of a component at rest, for containment queries at construction.
MeshQuery rest_surface_query(const Model& m, int component) {
  const Surface& s = m.surfaces[m.components[component].surface];
  TriMesh t;
  t.vertices = m.rest_pos;
  t.faces = s.faces;
  return MeshQuery(t);
}

}  // namespace

ProbeTool::ProbeTool(const ProbeSpec& spec, const Model& m) : spec_(spec), rectal_(rectal_frame(spec)) {
  int rectum = -1, prostate = -1;
  const std::vector<uint8_t> in_set = contact_set(m, rectum, prostate);
  pose_ = spec.pose;
  frame_ = check_start_pose(m, in_set, rectum);
  lengthen_scripted_moves();
  std::vector<uint8_t> on_constrained(m.particle_count(), 0);
  for (const Surface& s : m.surfaces)
    if (s.volume_constrained)
      for (int p : s.vertices) on_constrained[p] = 1;
  collect_candidates(m, in_set, on_constrained);
  build_broad_phase(m);
  if (spec.imposed_mode) couple_imposed(m, rectum, prostate, on_constrained);
  else couple_start_.assign(cand_.size() + 1, 0);
}

// Which components the probe pushes, and its rectum and (imposed mode) prostate; InputError naming
// the probe's field.
std::vector<uint8_t> ProbeTool::contact_set(const Model& m, int& rectum, int& prostate) const {
  const ProbeSpec& spec = spec_;
  const std::string& file = spec_.loc.file;
  const int line = spec_.loc.line;
  auto fail = [&](int at, const std::string& field, const std::string& msg) { throw InputError(file, at, field, msg); };
  auto component = [&](const std::string& name, const std::string& field) {
    const int c = m.find_component(name);
    if (c < 0) fail(line, field, "unknown component '" + name + "'");
    return c;
  };
  const int nc = static_cast<int>(m.components.size());
  std::vector<uint8_t> in_set(nc, 0);
  if (spec.contact_components.empty()) {
    for (int c = 0; c < nc; ++c) in_set[c] = m.components[c].kind != ComponentKind::Rigid;
  } else {
    for (const std::string& name : spec.contact_components) {
      const int c = component(name, "probe.contact.components");
      if (m.components[c].kind == ComponentKind::Rigid)
        fail(line, "probe.contact.components", "'" + name + "' is rigid: the probe cannot push it");
      in_set[c] = 1;
    }
  }
  if (!spec.rectum.empty()) rectum = component(spec.rectum, "probe.contact.rectum");
  else rectum = m.find_role(Role::Rectum);
  if (spec.imposed_mode) {
    if (rectum < 0 || spec.prostate.empty())
      fail(line, "probe.contact.mode", "mode imposed needs contact.rectum and contact.prostate components");
    prostate = component(spec.prostate, "probe.contact.prostate");
    if (prostate == rectum) fail(line, "probe.contact.prostate", "prostate and rectum must be different components");
    in_set[rectum] = 1;
  }

  return in_set;
}

// The start pose is inside the rectal lumen, clear of bone and of the tissue it pushes.
ProbeFrame ProbeTool::check_start_pose(const Model& m, const std::vector<uint8_t>& in_set, int rectum) const {
  const ProbeSpec& spec = spec_;
  const int nc = static_cast<int>(m.components.size());
  auto fail = [&](int at, const std::string& field, const std::string& msg) { throw InputError(spec.loc.file, at, field, msg); };
  if (!finite_pose(pose_)) fail(spec.pose_loc.line, "probe.pose", "non-finite pose value");
  const ProbeFrame frame = probe_frame(spec_, rectal_, pose_);
  const Capsule& cap = frame.capsule;
  const Vec3 axis_pts[3] = {cap.back, 0.5 * (cap.back + cap.tip), cap.tip};
  if (rectum >= 0 && m.components[rectum].surface >= 0) {
    const MeshQuery q = rest_surface_query(m, rectum);
    for (const Vec3& a : axis_pts)
      if (!q.inside(a))
        fail(spec.pose_loc.line, "probe.pose",
             "the probe is outside the rectum '" + m.components[rectum].name + "': its axis point (" + mm(a.x()) + ", " +
                 mm(a.y()) + ", " + mm(a.z()) + ") is not in the rectal lumen; check entry_mm, axis and insertion_mm");
  }
  for (int c = 0; c < nc; ++c) {
    const Component& comp = m.components[c];
    if (comp.kind != ComponentKind::Rigid) continue;
    bool inside = false;
    if (comp.surface >= 0) {
      const MeshQuery q = rest_surface_query(m, c);
      for (const Vec3& a : axis_pts) inside |= q.inside(a);
    }
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count && !inside; ++p)
      inside = capsule_signed_distance(cap, m.rest_pos[p]) < 0.0;
    if (inside) fail(spec.pose_loc.line, "probe.pose", "the probe starts inside the rigid component (bone) '" + comp.name + "'");
  }
  for (int p = 0; p < m.particle_count(); ++p) {
    const Component& comp = m.components[m.component_of[p]];
    if (!in_set[m.component_of[p]]) continue;  // tissue the probe is not asked to push may overlap
    const double d = capsule_signed_distance(cap, m.rest_pos[p]);
    if (d < -kProbePenetrationTolerance)
      fail(spec.pose_loc.line, "probe.pose",
           "the probe starts inside tissue: particle " + std::to_string(p) + " of '" + comp.name + "' is " + mm(-d) +
               " inside it; start the probe in the rectal lumen");
  }

  return frame;
}

// The scenario's moves, lengthened to the speed limits (a dry run of the schedule gives each
// move's starting pose), each lengthening reported.
void ProbeTool::lengthen_scripted_moves() {
  const ProbeSpec& spec = spec_;
  script_ = spec.moves;
  std::stable_sort(script_.begin(), script_.end(), [](const ProbeMoveSpec& a, const ProbeMoveSpec& b) { return a.t0 < b.t0; });
  Move act{0.0, 0.0, pose_, pose_};
  for (ProbeMoveSpec& mv : script_) {
    const ProbePose from = evaluate(act, mv.t0);
    const ProbePose to = merge(from, mv);
    const double need = min_duration(from, to);
    if (need > (mv.t1 - mv.t0) * (1.0 + 1e-12)) {
      ToolReport r;
      r.code = ToolReportCode::ProbeMoveLengthened;
      r.line = mv.loc.line;
      r.time = mv.t0;
      r.a = mv.t1 - mv.t0;
      r.b = need;
      r.c = spec.max_speed;
      r.d = spec.max_angular_speed;
      reports_.push(r);
      mv.t1 = mv.t0 + need;
    }
    act = Move{mv.t0, mv.t1, from, to};
  }
  active_ = Move{0.0, 0.0, pose_, pose_};
}

// Contact candidates: the particles of the pushed components, and bone (held, never moved).
void ProbeTool::collect_candidates(const Model& m, const std::vector<uint8_t>& in_set, const std::vector<uint8_t>& on_constrained) {
  for (int p = 0; p < m.particle_count(); ++p) {
    // held particles of the set and bone are candidates too, never moved: blocked_count()
    const bool bone = m.components[m.component_of[p]].kind == ComponentKind::Rigid;
    if (!in_set[m.component_of[p]] && !bone) continue;
    cand_.push_back(p);
    movable_.push_back(!bone && m.inv_mass[p] > 0.0 && m.locked_axes[p] == 0);
    cand_constrained_.push_back(on_constrained[p]);
    volume_coupled_ |= on_constrained[p] != 0;
  }
  hit_.assign(cand_.size(), 0);
}

// The FCL broad phase (ProbeBroadPhase::Fcl): a tree over the surfaces of the components that hold
// candidates; candidates on none of them are tested every substep.
void ProbeTool::build_broad_phase(const Model& m) {
  cand_of_.assign(m.particle_count(), -1);
  for (size_t i = 0; i < cand_.size(); ++i) cand_of_[cand_[i]] = static_cast<int>(i);
  std::vector<std::array<int, 3>> faces;
  std::vector<uint8_t> on_bvh(m.particle_count(), 0);
  for (const Surface& sf : m.surfaces) {
    if (sf.faces.empty() || cand_of_[sf.faces[0][0]] < 0) continue;  // a component's surface: all or none
    for (const auto& f : sf.faces) {
      faces.push_back(f);
      for (int p : f) on_bvh[p] = 1;
    }
  }
  for (size_t i = 0; i < cand_.size(); ++i)
    if (!on_bvh[cand_[i]]) loose_.push_back(static_cast<int>(i));
  if (!faces.empty()) fcl_ = std::make_unique<FclSurfaceContact>(faces, m.rest_pos);
  else broad_ = ProbeBroadPhase::Box;
  near_.reserve(cand_.size());
  near_mark_.assign(cand_.size(), 0);
}

// Imposed mode: each rectum candidate -> the prostate particles within couple_distance at rest.
void ProbeTool::couple_imposed(const Model& m, int rectum, int prostate, const std::vector<uint8_t>& on_constrained) {
  const ProbeSpec& spec = spec_;
  const int line = spec.loc.line;
  auto fail = [&](int at, const std::string& field, const std::string& msg) { throw InputError(spec.loc.file, at, field, msg); };
  couple_start_.assign(cand_.size() + 1, 0);
  const Component& R = m.components[rectum];
  const Component& P = m.components[prostate];
  const double dist = spec.couple_distance > 0.0 ? spec.couple_distance : 1.5 * std::max(R.spacing, P.spacing);
  std::vector<int> slot_of(m.particle_count(), -1);
  for (size_t i = 0; i < cand_.size(); ++i) {
    couple_start_[i] = static_cast<int>(couple_slot_.size());
    const int p = cand_[i];
    if (m.component_of[p] != rectum) continue;
    for (int t = P.first_particle; t < P.first_particle + P.particle_count; ++t) {
      if (m.inv_mass[t] == 0.0 || m.locked_axes[t] != 0) continue;
      if ((m.rest_pos[t] - m.rest_pos[p]).norm() > dist) continue;
      if (slot_of[t] < 0) {
        slot_of[t] = static_cast<int>(target_.size());
        target_.push_back(t);
        volume_coupled_ |= on_constrained[t] != 0;
      }
      couple_slot_.push_back(slot_of[t]);
    }
  }
  couple_start_[cand_.size()] = static_cast<int>(couple_slot_.size());
  if (target_.empty())
    fail(line, "probe.contact.couple_distance_mm",
         "no particle of '" + P.name + "' lies within " + mm(dist) + " of '" + R.name +
             "' at rest: the imposed mode needs the prostate to touch the rectum");
  local_.assign(target_.size(), Vec3::Zero());
  coupled_.assign(target_.size(), 0);
  touched_.assign(target_.size(), 0);
}

ProbePose ProbeTool::evaluate(const Move& mv, double t) {
  if (t >= mv.t1) return mv.to;
  if (t <= mv.t0) return mv.from;
  const double s = (t - mv.t0) / (mv.t1 - mv.t0);
  const double w = s * s * (3.0 - 2.0 * s);  // smoothstep: zero velocity at both ends
  ProbePose p;
  p.insertion = mv.from.insertion + w * (mv.to.insertion - mv.from.insertion);
  p.offset = mv.from.offset + w * (mv.to.offset - mv.from.offset);
  p.roll = mv.from.roll + w * (mv.to.roll - mv.from.roll);
  p.tilt = mv.from.tilt + w * (mv.to.tilt - mv.from.tilt);
  p.yaw = mv.from.yaw + w * (mv.to.yaw - mv.from.yaw);
  return p;
}

double ProbeTool::min_duration(const ProbePose& a, const ProbePose& b) const {
  const double lin = std::abs(b.insertion - a.insertion) + (b.offset - a.offset).norm();
  const double ang = std::abs(b.roll - a.roll) + std::abs(b.tilt - a.tilt) + std::abs(b.yaw - a.yaw);
  return 1.5 * std::max(lin / spec_.max_speed, ang / spec_.max_angular_speed);  // smoothstep peak = 1.5 x mean
}

void ProbeTool::advance_to(double t) {
  while (next_ < script_.size() && script_[next_].t0 <= t) {
    const ProbeMoveSpec& mv = script_[next_++];
    const ProbePose from = evaluate(active_, mv.t0);
    active_ = Move{mv.t0, mv.t1, from, merge(from, mv)};
  }
  pose_ = evaluate(active_, t);
  now_ = t;
  frame_ = probe_frame(spec_, rectal_, pose_);
  const Capsule& c = frame_.capsule;
  lo_ = c.back.cwiseMin(c.tip) - Vec3::Constant(c.radius + kProbeQueryMargin);  // box broad phase
  hi_ = c.back.cwiseMax(c.tip) + Vec3::Constant(c.radius + kProbeQueryMargin);
}

const char* ProbeTool::check_move(const ProbePose& target, double duration) {
  if (!finite_pose(target) || !std::isfinite(duration)) return "non-finite pose or duration";
  if (duration < 0.0) return "negative duration";
  if (std::abs(target.tilt) > kProbeMaxTiltRad || std::abs(target.yaw) > kProbeMaxTiltRad)
    return "tilt and yaw must be within +-45 degrees";
  return nullptr;
}

double ProbeTool::move_to(const ProbePose& target, double duration) {
  if (const char* why = check_move(target, duration)) throw InputError("", 0, "probe.move_to", why);
  advance_to(now_);  // scripted moves due now start before this command takes over
  const double need = min_duration(pose_, target);
  const double used = std::max(duration, need);
  if (used > duration * (1.0 + 1e-12)) {  // a record, no text: this runs on the physics thread (tool_reports.h)
    ToolReport r;
    r.code = ToolReportCode::ProbeMoveLengthened;
    r.live = 1;
    r.time = now_;
    r.a = duration;
    r.b = used;
    r.c = spec_.max_speed;
    r.d = spec_.max_angular_speed;
    reports_.push(r);
  }
  active_ = Move{now_, now_ + used, pose_, target};
  return used;
}

void ProbeTool::boundary_conditions(const Model&, State& s, double dt) { advance_to(s.time + dt); }

void ProbeTool::add_reaction(const Vec3& x_new, const Vec3& dx, double mass, double inv_dt2) {
  const Vec3 f = -mass * inv_dt2 * dx;  // tissue on probe = -(probe on tissue)
  force_acc_ += f;
  torque_acc_ += (x_new - frame_.pivot).cross(f);
}

void ProbeTool::find_candidates(const State& s) {
  near_.clear();
  const size_t nc = cand_.size();
  if (broad_ == ProbeBroadPhase::Box) {
    for (size_t i = 0; i < nc; ++i) {
      const Vec3& x = s.x[cand_[i]];
      if ((x.array() < lo_.array()).any() || (x.array() > hi_.array()).any()) continue;
      near_.push_back(static_cast<int>(i));
    }
    return;
  }
  const Capsule& c = frame_.capsule;
  fcl_->refit(s.x);
  fcl_->collide_capsule(c.back, c.tip, c.radius + kProbeQueryMargin);
  for (int f : fcl_->hits())
    for (int p : fcl_->faces()[f]) {
      const int i = cand_of_[p];
      if (!near_mark_[i]) { near_mark_[i] = 1; near_.push_back(i); }
    }
  for (int i : loose_) {  // interior particles: the capsule's box
    const Vec3& x = s.x[cand_[i]];
    if ((x.array() < lo_.array()).any() || (x.array() > hi_.array()).any()) continue;
    near_mark_[i] = 1;
    near_.push_back(i);
  }
  for (int i : near_) near_mark_[i] = 0;
  std::sort(near_.begin(), near_.end());  // candidate order, as the box pass: identical sums
}

double ProbeTool::contact_pass(const Model& m, State& s, double inv_dt2) {
  const Capsule& c = frame_.capsule;
  double max_dx = 0.0;
  for (const int i : near_) {
    if (!movable_[i]) continue;
    const int p = cand_[i];
    const Vec3& x = s.x[p];
    Vec3 q;
    const double d = capsule_signed_distance(c, x, &q);
    if (d >= 0.0) continue;
    const Vec3 r = x - q;
    const double len = r.norm();
    const Vec3 nrm = len > 1e-12 ? Vec3(r / len) : frame_.anterior();  // on the axis: push anteriorly
    const Vec3 xn = q + c.radius * nrm;
    const Vec3 dx = xn - x;
    add_reaction(xn, dx, 1.0 / m.inv_mass[p], inv_dt2);  // inertial mass (solver.mass_scaling)
    max_dx = std::max(max_dx, dx.norm());
    s.x[p] = xn;
    s.contact[p] = 7;
    if (!hit_[i]) { hit_[i] = 1; ++contacts_; }
  }
  return max_dx;
}

void ProbeTool::imposed_pass(const Model& m, State& s, double inv_dt2) {
  // prostate particles coupled to a rectum particle the probe holds this substep ride rigidly on
  // the probe from the moment the coupling starts (kinematic: their motion is the probe's)
  int nt = 0;
  const size_t nc = cand_.size();
  for (size_t i = 0; i < nc; ++i) {
    if (!hit_[i]) continue;
    for (int k = couple_start_[i]; k < couple_start_[i + 1]; ++k) {
      const int slot = couple_slot_[k];
      if (!touched_[slot]) { touched_[slot] = 1; ++nt; }
    }
  }
  const Vec3& o = frame_.capsule.tip;
  const Mat3& R = frame_.rot;
  const size_t ns = target_.size();
  for (size_t slot = 0; slot < ns; ++slot) {
    if (!touched_[slot]) { coupled_[slot] = 0; continue; }  // released: free tissue again
    touched_[slot] = 0;
    const int t = target_[slot];
    if (!coupled_[slot]) {  // coupling starts where the particle is: no jump
      local_[slot] = R.transpose() * (s.x[t] - o);
      coupled_[slot] = 1;
    }
    const Vec3 xn = o + R * local_[slot];
    add_reaction(xn, xn - s.x[t], 1.0 / m.inv_mass[t], inv_dt2);  // movable: inv_mass > 0
    s.x[t] = xn;
    s.contact[t] = 7;
  }
  imposed_ = std::max(imposed_, nt);
}

// By the exact distance, not by membership of near_: both broad phases hold every candidate within
// the margin, the box more besides, and the two must decide alike to give the same bits.
bool ProbeTool::constrained_vertex_near(const State& s) const {
  for (const int i : near_)
    if (cand_constrained_[i] && capsule_signed_distance(frame_.capsule, s.x[cand_[i]]) < kProbeQueryMargin) return true;
  return false;
}

void ProbeTool::constraints(const Model& m, State& s, double dt) {
  const double inv_dt2 = 1.0 / (dt * dt);
  std::fill(hit_.begin(), hit_.end(), 0);
  contacts_ = 0;
  imposed_ = 0;
  find_candidates(s);
  contact_pass(m, s, inv_dt2);
  if (spec_.imposed_mode) imposed_pass(m, s, inv_dt2);
  if (!volume_coupled_) return;
  // the volume projection comes next and may push free vertices of a constrained surface into
  // the probe: alternate here until the contact corrections are negligible. Only vertices near the
  // probe can be pushed into it; with none this substep, the engine's volume stage projects alone
  // (probe.h, "Penetration"). Imposed mode alternates always: its targets ride on the probe.
  if (!spec_.imposed_mode && !constrained_vertex_near(s)) return;
  ++volume_alternations_;
  for (int it = 0; it < kProbeVolumeIterations; ++it) {
    if (!project_volumes(m, s)) return;  // fault recorded; the step reports it
    const double moved = contact_pass(m, s, inv_dt2);
    if (spec_.imposed_mode) imposed_pass(m, s, inv_dt2);
    if (moved < kVolumeLoopStop) break;
  }
}

void ProbeTool::after_step(const Model& m, State& s, double) {
  const Capsule& c = frame_.capsule;
  double pen = 0.0;
  int blocked = 0;
  for (const int i : near_) {  // this substep's candidates (see the broad phase in probe.h)
    const Vec3& x = s.x[cand_[i]];
    const double d = capsule_signed_distance(c, x);
    if (d >= 0.0) continue;
    if (movable_[i]) pen = std::max(pen, -d);
    else ++blocked;
  }
  penetration_ = pen;
  penetration_seen_ = std::max(penetration_seen_, pen);
  blocked_ = blocked;
  if (blocked > 0) ++blocked_substeps_;
  if (++substeps_acc_ >= m.substeps) {
    force_ = force_acc_ / substeps_acc_;
    torque_ = torque_acc_ / substeps_acc_;
    force_acc_.setZero();
    torque_acc_.setZero();
    substeps_acc_ = 0;
  }
}

std::unique_ptr<ProbeTool> make_probe_tool(const ScenarioSpec& spec, const Model& model) {
  if (!spec.probe) return nullptr;
  return std::make_unique<ProbeTool>(*spec.probe, model);
}

}  // namespace ps
