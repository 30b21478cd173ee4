// NeedleTool: construction (its steps in needle_setup.cpp), the per-substep hooks in the order of Algorithm 2, and read-outs.
#include "engine/tools/needle/needle.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <numeric>

#include "engine/model/role.h"
#include "engine/tools/bone_contact.h"
#include "engine/tools/needle/needle_internal.h"
#include "engine/tools/probe/probe.h"
#include "engine/util/error.h"

namespace ps {

const char* needle_event_name(NeedleEventKind k) {
  switch (k) {
    case NeedleEventKind::Contact: return "contact";
    case NeedleEventKind::Puncture: return "puncture";
    case NeedleEventKind::Stick: return "stick";
    case NeedleEventKind::Slip: return "slip";
    case NeedleEventKind::Seed: return "seed";
    case NeedleEventKind::Core: return "core";
    case NeedleEventKind::BoneHit: return "bone_hit";
    case NeedleEventKind::ForceClamped: return "force_clamped";
    case NeedleEventKind::Urethra: return "urethra";
    case NeedleEventKind::GlandExit: return "out of the gland through";
  }
  return "?";
}

NeedleTool::NeedleTool(std::shared_ptr<const Model> model, const NeedleSetSpec& set)
    : model_(std::move(model)), events_(set.event_capacity) {
  const Model& m = *model_;
  puncture_kc_ = needle_puncture_weights(m, set);
  if (!m.rigid_bodies.empty()) bone_ = std::make_unique<BoneContact>(m);
  membranes_ = needle_membrane_faces(m, puncture_kc_);
  const TissueExtent extent = tissue_extent(m);
  double m_min = std::numeric_limits<double>::infinity();  // lightest particle any path plans so far [kg]
  for (size_t i = 0; i < set.needles.size(); ++i)
    needles_.push_back(plan_needle(m, set.needles[i], static_cast<int>(i), extent, *membranes_, puncture_kc_, m_min, warnings_));
  budget_ = std::make_unique<CouplingBudget>();
  budget_->g.assign(m.particle_count(), 0.0);
  budget_->touched.reserve(m.particle_count());
  for (auto& nd : needles_) {
    nd->ro.tip = nd->T;
    nd->ro.direction = nd->d;
    nd->ro.command_tip = nd->T;
  }
}

NeedleTool::~NeedleTool() = default;

void NeedleTool::forces(const Model& m, State& s, double dt) {
  // Algorithm 2 for each needle: zones and their virtual particles, then (once every needle's
  // anchors are known) the stability bound of their summed coupling, then the tissue forces per
  // node (stick/slide) and the needle movement. The zones depend on the positions only, so
  // zoning every needle first changes nothing but lets the bound see all of them.
  for (auto& p : needles_) {
    if (p->guided && probe_) follow_guide(*p, m, s, probe_->biopsy_guide());
    update_needle_zones(*p, m, s, puncture_kc_, *membranes_, events_);
    prepare_needle_anchors(*p, s);
  }
  bound_needle_coupling(needles_, m, dt, *budget_);
  coupling_stats_.bound = budget_->peak;
  coupling_stats_.bound_applied = budget_->after;
  coupling_stats_.softened_nodes = budget_->softened;
  coupling_stats_.bound_max = std::max(coupling_stats_.bound_max, budget_->peak);
  coupling_stats_.softened_substeps += budget_->softened > 0;
  for (auto& p : needles_) {
    Needle& nd = *p;
    const Vec3 f_tissue = apply_needle_tissue_forces(nd, m, s, puncture_kc_, *membranes_, dt, events_);
    move_needle(nd, m, s, f_tissue, dt, bone_.get(), events_);
  }
}

void NeedleTool::after_step(const Model& m, State& s, double) {
  if (!urethra_rest_.empty() && s.step % m.substeps == 0) check_urethra(m, s);
  if (gland_ >= 0 && s.step % m.substeps == 0) check_gland_exit(m, s);
  for (auto& p : needles_) {
    Needle& nd = *p;
    update_seeds(nd, m, s, events_);
    update_biopsy(nd, m, s, events_);
    rearm_in_guide(nd, s.time);
    NeedleReadout& ro = nd.ro;
    ro.tip = nd.T;
    ro.direction = nd.d;
    ro.velocity = nd.V;
    ro.plan_depth = nd.guided ? (nd.T - nd.guide_now.entry).dot(nd.guide_now.direction) : plan_depth(nd);
    ro.depth = insertion_depth(nd);
    ro.contacted = nd.contacted;
    if (nd.phase_blocked > 0) { --nd.phase_blocked; ro.phase = NeedlePhase::Blocked; }
    else if (nd.press_n > 0) ro.phase = NeedlePhase::Pressing;
    else if (ro.engaged_nodes > 0) ro.phase = NeedlePhase::Inserted;
    else ro.phase = NeedlePhase::Outside;
    nd.tick_sum += ro.axial_force;
    ++nd.tick_n;
    if (s.step % m.substeps == 0) {
      ro.axial_force_tick = nd.tick_sum / nd.tick_n;
      nd.tick_sum = 0.0;
      nd.tick_n = 0;
    }
  }
}

int NeedleTool::find(const std::string& name) const {
  for (size_t i = 0; i < needles_.size(); ++i)
    if (needles_[i]->spec.name == name) return static_cast<int>(i);
  return -1;
}
const NeedleSpec& NeedleTool::spec(int i) const { return needles_.at(i)->spec; }
const NeedleReadout& NeedleTool::readout(int i) const { return needles_.at(i)->ro; }
const NeedleZoneStats& NeedleTool::stats(int i) const { return needles_.at(i)->stats; }

void NeedleTool::command(int i, const Vec3& tip, const Vec3& direction, const Vec3& velocity) {
  Needle& nd = *needles_.at(i);
  if (!(direction.norm() > 0.0) || !tip.allFinite() || !velocity.allFinite())
    throw InputError("", 0, nd.spec.key + ".command", "needle command needs a finite tip, velocity and a non-zero direction");
  nd.interactive = true;
  nd.cmd_T = tip;
  nd.cmd_d = direction.normalized();
  nd.cmd_V = velocity;
}

void NeedleTool::release_command(int i) { needles_.at(i)->interactive = false; }

void NeedleTool::fire(int i, double now) {
  Needle& nd = *needles_.at(i);
  if (!nd.spec.gun) throw InputError(nd.spec.file, nd.spec.line, nd.spec.key + ".gun", "needle '" + nd.spec.name + "' has no biopsy gun");
  nd.fire_time = now;   // the stroke ramps in from `now` (needle_command), scripted or interactive
  nd.core.taken = false;
}

std::vector<SeedReport> NeedleTool::seeds() const {
  std::vector<SeedReport> out;
  for (const auto& p : needles_)
    for (size_t k = 0; k < p->seeds.size(); ++k) {
      const SeedState& sd = p->seeds[k];
      SeedReport r;
      r.needle = p->index;
      r.index = static_cast<int>(k);
      r.deposited = sd.deposited;
      r.embedded = sd.embedded;
      r.time = sd.time;
      r.planned = sd.planned;
      r.deposited_at = sd.at;
      r.current = sd.current;
      r.error = sd.deposited ? (sd.current - sd.planned).norm() : 0.0;
      out.push_back(r);
    }
  return out;
}

namespace {

CoreReport core_report(const Model& m, const NeedleTool::Needle& nd, const CoreState& core) {
  CoreReport r;
  r.needle = nd.index;
  r.taken = core.taken;
  r.time = core.time;
  r.particles = core.particles;
  for (size_t c = 0; c < core.per_component.size(); ++c)
    if (core.per_component[c] > 0) r.per_component.emplace_back(m.components[c].name, core.per_component[c]);
  for (size_t t = 0; t < core.per_tag.size(); ++t)
    if (core.per_tag[t] > 0) r.per_tag.emplace_back(m.tag_names[t], core.per_tag[t]);
  r.tumour_particles = core.tumour_particles;
  r.tumour_length = core.tumour_length;
  r.notch_length = nd.spec.gun ? nd.spec.gun->notch_length : 0.0;
  if (nd.spec.gun) {
    const double back = nd.spec.gun->notch_offset + 0.5 * nd.spec.gun->notch_length;
    r.notch_centre = core.tip - back * core.direction;
  }
  r.direction = core.direction;
  return r;
}

}  // namespace

CoreReport NeedleTool::core(int i) const {
  const Needle& nd = *needles_.at(i);
  return core_report(*model_, nd, nd.core);
}

std::vector<CoreReport> NeedleTool::cores(int i) const {
  const Needle& nd = *needles_.at(i);
  std::vector<CoreReport> out;
  for (int k = 0; k < nd.cores_done_n; ++k) out.push_back(core_report(*model_, nd, nd.cores_done[k]));
  if (nd.core.taken) out.push_back(core_report(*model_, nd, nd.core));
  return out;
}

bool NeedleTool::guided(int i) const { return needles_.at(i)->guided; }

void NeedleTool::attach_probe(const ProbeTool* probe) {
  probe_ = probe;
  if (!probe) return;
  for (auto& p : needles_)
    if (p->guided) {
      p->guide_now = p->guide_prev = probe->biopsy_guide();
      Vec3 v0;
      needle_command(*p, 0.0, p->T, p->d, v0);
      p->ro.tip = p->ro.command_tip = p->T;
      p->ro.direction = p->d;
    }
}

std::vector<Vec3> NeedleTool::nodes(int i) const {
  const Needle& nd = *needles_.at(i);
  std::vector<Vec3> out;
  for (int j = 0; j < nd.node_count; ++j) out.push_back(needle_node(nd, j));
  return out;
}

std::vector<int> NeedleTool::zone_particles(int i, int node) const {
  const Needle& nd = *needles_.at(i);
  if (node < 0 || node >= nd.node_count) return {};
  const int* zi = &nd.zone_idx[static_cast<size_t>(node) * kZoneCapacity];
  return std::vector<int>(zi, zi + nd.zone_n[node]);
}

std::vector<int> NeedleTool::cutting_particles(int i) const {
  const Needle& nd = *needles_.at(i);
  return std::vector<int>(nd.cut_idx.begin(), nd.cut_idx.begin() + nd.cut_n);
}

bool NeedleTool::node_stuck(int i, int node) const { return needles_.at(i)->stuck.at(node) != 0; }
bool NeedleTool::node_anchor_rotational(int i, int node) const { return needles_.at(i)->anchors.at(node).rotational; }
bool NeedleTool::component_entered(int i, int component) const { return needles_.at(i)->entered.at(component) != 0; }

std::unique_ptr<NeedleTool> make_needle_tool(std::shared_ptr<const Model> model, const NeedleSetSpec& spec) {
  if (spec.needles.empty()) return nullptr;
  return std::make_unique<NeedleTool>(std::move(model), spec);
}

}  // namespace ps
