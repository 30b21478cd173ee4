// A needle in the probe's biopsy guide (NeedleSpec::guide): the probe and the loaded guide are one
// rigid assembly, so the needle's entry and direction are the guide's at the probe's pose of every
// substep and the needle's coupling spring drags its tip (and, through its friction anchors, the
// tissue around the shaft) with the probe. The trainee aims by turning, angling and pushing the
// probe; the needle's depth is commanded live. After a core the needle is withdrawn into the
// guide, re-armed, and fires again: a 12-core biopsy with one needle.
#include <algorithm>

#include "engine/tools/needle/needle_internal.h"

namespace ps {

namespace {

// the planned line is rebuilt when the guide's path has moved this far from it (fraction of
// plan_margin, measured at the exit and kPlanCheckDepth along it)
constexpr double kReplanFraction = 0.25;
constexpr double kPlanCheckDepth = 80e-3;  // [m] beyond the gland's far capsule in the default anatomy
// a tip commanded within this of the guide's exit is back in the guide (re-armed) [m]; not 0: the
// stroke folded into and out of the command leaves rounding either side of it
constexpr double kRearmDepth = 0.5e-3;

}  // namespace

void follow_guide(NeedleTool::Needle& nd, const Model& m, const State& s, const NeedlePath& guide) {
  nd.guide_prev = nd.guide_now;
  nd.guide_now = guide;
  const Vec3& S = nd.spec.start;
  const Vec3& d = nd.spec.direction;
  const double off_entry = (guide.entry - S).norm();
  const double off_far = (guide.entry + kPlanCheckDepth * guide.direction - (S + kPlanCheckDepth * d)).norm();
  if (std::max(off_entry, off_far) <= kReplanFraction * nd.spec.plan_margin) return;
  // the particles near the guide's line now (current positions), sorted along it
  nd.spec.start = guide.entry;
  nd.spec.direction = guide.direction;
  const double reach = nd.plan_reach, len = nd.spec.length + 2.0 * reach;
  const Vec3 a = guide.entry - reach * guide.direction;
  nd.plan_scratch.clear();
  const int n = m.particle_count();
  for (int p = 0; p < n; ++p) {
    if (!(m.inv_mass[p] > 0.0) || m.components[m.component_of[p]].kind == ComponentKind::Rigid) continue;
    const Vec3 rel = s.x[p] - a;
    const double u = std::clamp(rel.dot(guide.direction), 0.0, len);
    if ((rel - u * guide.direction).squaredNorm() > reach * reach) continue;
    nd.plan_scratch.emplace_back((s.x[p] - guide.entry).dot(guide.direction), p);
  }
  std::sort(nd.plan_scratch.begin(), nd.plan_scratch.end());
  nd.plan_t.clear();
  nd.plan_idx.clear();
  for (const auto& [t, p] : nd.plan_scratch) {
    nd.plan_t.push_back(t);
    nd.plan_idx.push_back(p);
  }
  nd.seed_counter = 0;
}

void rearm_in_guide(NeedleTool::Needle& nd, double t) {
  if (!nd.guided || !nd.spec.gun || std::isnan(nd.fire_time) || !nd.core.taken) return;
  if (guide_depth(nd, t) > kRearmDepth) return;
  if (nd.cores_done_n < kMaxGuideCores) nd.cores_done[nd.cores_done_n++] = nd.core;  // capacity reserved: no allocation
  nd.cmd_depth = guide_depth(nd, t);  // the stroke folds into the command: the tip stays where it is
  nd.cmd_speed = nd.interactive ? nd.cmd_speed : 0.0;
  nd.interactive = true;
  nd.cmd_t0 = t;
  nd.fire_time = NAN;
  nd.core.taken = false;
}

void reset_contact_in_lumen(NeedleTool::Needle& nd, const MembraneFaces& mf) {
  for (size_t c = 0; c < nd.entered.size(); ++c)
    if (!mf.sheet[c]) nd.entered[c] = 0;
  nd.contacted = false;
  nd.contact_axial = 0.0;
  nd.peak_force = 0.0;
  nd.near_urethra = false;
  nd.exit_a = -1e300;
}

}  // namespace ps
