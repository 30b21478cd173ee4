// What NeedleTool's constructor assigns, each step a named function (needle_internal.h): the
// puncture weights and membrane faces it checks against the model, and per needle its plan:
// the particles its path can meet, its buffers sized once, its place in the probe's guide, what it
// starts inside, its seeds, what counts as tumour, and a warning for springs too stiff for the
// substep. Each throws InputError naming the needle's field on bad input.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "engine/model/role.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/needle/needle_internal.h"
#include "engine/util/error.h"

namespace ps {

namespace {

bool eligible(const Model& m, int p) {
  return m.inv_mass[p] > 0.0 && m.components[m.component_of[p]].kind != ComponentKind::Rigid;
}

// Point inside a closed surface at rest (ray parity along a direction no lattice is aligned with).
bool inside_rest_surface(const Model& m, const Surface& surf, const Vec3& q) {
  const Vec3 dir = Vec3(0.5773, 0.5411, 0.6113).normalized();
  int hits = 0;
  for (const auto& f : surf.faces) {
    const Vec3 &a = m.rest_pos[f[0]], &b = m.rest_pos[f[1]], &c = m.rest_pos[f[2]];
    const Vec3 e1 = b - a, e2 = c - a, pv = dir.cross(e2);
    const double det = e1.dot(pv);
    if (std::abs(det) < 1e-18) continue;
    const double inv = 1.0 / det;
    const Vec3 tv = q - a;
    const double u = tv.dot(pv) * inv;
    if (u < 0.0 || u > 1.0) continue;
    const Vec3 qv = tv.cross(e1);
    const double v = dir.dot(qv) * inv;
    if (v < 0.0 || u + v > 1.0) continue;
    if (e2.dot(qv) * inv > 0.0) ++hits;
  }
  return hits % 2 == 1;
}

// Distance from point p to segment [a, a + len * dir] and the parameter of the closest point.
double segment_distance(const Vec3& a, const Vec3& dir, double len, const Vec3& p, double* t_out = nullptr) {
  const double t = std::clamp((p - a).dot(dir), 0.0, len);
  if (t_out) *t_out = t;
  return (p - (a + t * dir)).norm();
}


}  // namespace

std::vector<double> needle_puncture_weights(const Model& m, const NeedleSetSpec& set) {
  const int nc = static_cast<int>(m.components.size());
  std::vector<double> puncture_kc;
  puncture_kc.assign(nc, 0.0);
  for (const auto& [name, kc] : set.puncture) {
    const int c = m.find_component(name);
    if (c < 0) throw InputError(set.file, set.line, "needles.puncture_n." + name, "unknown component '" + name + "'");
    if (m.components[c].kind == ComponentKind::Rigid)
      throw InputError(set.file, set.line, "needles.puncture_n." + name, "'" + name + "' is rigid: needles stop on bone, they do not puncture it");
    puncture_kc[c] = kc;
  }
  return puncture_kc;
}

std::unique_ptr<MembraneFaces> needle_membrane_faces(const Model& m, const std::vector<double>& puncture_kc) {
  const int n = m.particle_count();
  const int nc = static_cast<int>(m.components.size());
  // membrane surfaces: faces incident to each particle (CSR)
  auto out = std::make_unique<MembraneFaces>();
  MembraneFaces& mf = *out;
  mf.sheet.assign(nc, 0);
  for (int c = 0; c < nc; ++c) mf.sheet[c] = !m.components[c].volumetric;
  for (int c = 0; c < nc; ++c) {
    if (!(puncture_kc[c] > 0.0) || m.components[c].surface < 0) continue;
    mf.max_puncture = std::max(mf.max_puncture, puncture_kc[c]);
    for (const auto& f : m.surfaces[m.components[c].surface].faces) {
      mf.faces.push_back(f);
      mf.face_component.push_back(c);
    }
  }
  mf.start.assign(n + 1, 0);
  for (const auto& f : mf.faces)
    for (int v : f) ++mf.start[v + 1];
  for (int p = 0; p < n; ++p) mf.start[p + 1] += mf.start[p];
  mf.list.assign(mf.start[n], 0);
  {
    std::vector<int> fill(mf.start.begin(), mf.start.end() - 1);
    for (size_t f = 0; f < mf.faces.size(); ++f)
      for (int v : mf.faces[f]) mf.list[fill[v]++] = static_cast<int>(f);
  }
  return out;
}

TissueExtent tissue_extent(const Model& m) {
  TissueExtent e;
  const int n = m.particle_count();
  // the scene: box of the tissue particles and the largest tissue spacing
  e.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  e.hi = -e.lo;
  for (int p = 0; p < n; ++p) {
    if (!eligible(m, p)) continue;
    e.lo = e.lo.cwiseMin(m.rest_pos[p]);
    e.hi = e.hi.cwiseMax(m.rest_pos[p]);
  }
  for (const Component& c : m.components)
    if (c.kind != ComponentKind::Rigid) e.h_global = std::max(e.h_global, c.spacing);
  return e;
}

void size_needle_buffers(NeedleTool::Needle& nd, const Model& m, const MembraneFaces& mf) {
  const int n = m.particle_count();
  const int nc = static_cast<int>(m.components.size());
  const double h_sub = m.dt / m.substeps;
  nd.tracked.reserve(n);
  nd.next.reserve(n);
  nd.mark.assign(n, 0);
  nd.face_epoch.assign(mf.faces.size(), 0);
  nd.face_breached.assign(mf.faces.size(), 0);
  nd.entered.assign(nc, 0);
  nd.zone_idx.assign(static_cast<size_t>(nd.node_count) * kZoneCapacity, -1);
  nd.zone_dist.assign(static_cast<size_t>(nd.node_count) * kZoneCapacity, 0.0);
  nd.zone_n.assign(nd.node_count, 0);
  nd.anchors.assign(nd.node_count, AffineAnchor{});
  nd.anchor_c.assign(static_cast<size_t>(nd.node_count) * kAnchorMaxNeighbours, 0.0);
  nd.anchor_csum.assign(nd.node_count, 0.0);
  nd.stick_scale.assign(nd.node_count, 1.0);
  nd.stick_scale_used.assign(nd.node_count, 1.0);
  nd.stuck.assign(nd.node_count, 1);
  nd.reported.assign(nd.node_count, 255);
  nd.pending.assign(nd.node_count, 0);
  nd.debounce = std::max(1, static_cast<int>(std::lround(2e-3 / h_sub)));
  nd.fire_time = nd.spec.gun ? nd.spec.gun->fire_time : NAN;
}

void resolve_tumour(NeedleTool::Needle& nd, const Model& m) {
  const NeedleSpec& spec = nd.spec;
  const int nc = static_cast<int>(m.components.size());
  nd.tumour.assign(nc, 0);
  if (!spec.tumour.empty()) {
    for (size_t k = 0; k < spec.tumour.size(); ++k) {
      const int c = m.find_component(spec.tumour[k]);
      const int t = m.find_tag(spec.tumour[k]);
      if (c < 0 && t < 0)
        throw InputError(spec.file, spec.line, spec.key + ".tumour[" + std::to_string(k) + "]",
                         "'" + spec.tumour[k] + "' is neither a component nor a tag");
      if (c >= 0) nd.tumour[c] = 1;
      if (t >= 0) nd.tumour_tags |= uint64_t{1} << t;
    }
  } else {
    for (int c = 0; c < nc; ++c) nd.tumour[c] = m.components[c].role == Role::Lesion;
    for (size_t t = 0; t < m.tag_names.size(); ++t)
      if (m.tag_role(static_cast<int>(t)) == Role::Lesion) nd.tumour_tags |= uint64_t{1} << t;
  }
}

void check_needle_stiffness(const NeedleSpec& spec, const Model& m, double h_sub, double m_min, std::vector<std::string>& warnings) {
  // explicit springs on particles: press and virtual-particle stiffness vs the substep, with the
  // margin the compiler keeps for the tissue (0.9 of the explicit limit 2 sqrt(m / k), m the
  // lightest particle). The press force is also capped at the puncture threshold and critically
  // damped (needle_forces.cpp) and the stick springs are bounded per substep by the coupling
  // budget (needle_coupling.cpp), so this flags a spring beyond the explicit limit itself (a
  // margin of 0.5 would flag the default scenes, whose needle force is within the error budget).
  const double k_tool = std::max(spec.press_stiffness, spec.stick_stiffness);
  if (std::isfinite(m_min) && h_sub > 0.9 * 2.0 * std::sqrt(m_min / k_tool))
    warnings.push_back("needle '" + spec.name + "': press/stick stiffness " + std::to_string(k_tool) +
                        " N/m is stiff for the substep " + std::to_string(h_sub) + " s and particle mass " +
                        std::to_string(m_min) + " kg; lower it or add substeps");
}

std::unique_ptr<NeedleTool::Needle> plan_needle(const Model& m, const NeedleSpec& spec, int index, const TissueExtent& ext,
                                                const MembraneFaces& mf, const std::vector<double>& puncture_kc, double& m_min,
                                                std::vector<std::string>& warnings) {
  const int n = m.particle_count();
  const int nc = static_cast<int>(m.components.size());
  const double h_sub = m.dt / m.substeps;
  const Vec3 &lo = ext.lo, &hi = ext.hi;
  const double h_global = ext.h_global;
  validate_needle_spec(spec);
  auto nd_ptr = std::make_unique<NeedleTool::Needle>();
  NeedleTool::Needle& nd = *nd_ptr;
  nd.spec = spec;
  nd.index = index;
  nd.radius = 0.5 * spec.diameter;
  nd.node_count = static_cast<int>(std::floor(spec.length / spec.node_spacing + 1e-9)) + 1;
  nd.node_scale = spec.node_spacing / 1e-3;
  const Vec3 S = spec.start, d0 = spec.direction;
  double max_depth = spec.length;
  if (!spec.script.empty()) {
    max_depth = 0.0;
    for (const auto& p : spec.script) max_depth = std::max(max_depth, p.depth);
    if (spec.gun) max_depth += spec.gun->stroke;
  }
  const double given_r = std::max(spec.cutting_radius, spec.friction_radius);
  // first pass with the scene's largest spacing: which particles could the needle ever meet?
  const double reach0 = std::max(given_r, h_global) + h_global + spec.plan_margin;
  const double t_lo = -reach0, t_len = max_depth + 2.0 * reach0;
  const Vec3 a0 = S + t_lo * d0;
  std::vector<std::pair<double, int>> cand;
  double h_near = 0.0;
  for (int p = 0; p < n; ++p) {
    if (!eligible(m, p)) continue;
    double t;
    if (segment_distance(a0, d0, t_len, m.rest_pos[p], &t) > reach0) continue;
    cand.emplace_back((m.rest_pos[p] - S).dot(d0), p);
    h_near = std::max(h_near, m.components[m.component_of[p]].spacing);
  }
  if (cand.empty()) {
    // distance from the path to the scene box, for the message
    double gap = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 200; ++k) {
      const Vec3 q = S + (max_depth * k / 200.0) * d0;
      gap = std::min(gap, (lo - q).cwiseMax(q - hi).cwiseMax(Vec3::Zero()).norm());
    }
    throw InputError(spec.file, spec.line, spec.key + ".start_mm",
                     "needle '" + spec.name + "' is outside the scene: its path (start_mm, direction, " +
                         std::to_string(max_depth * 1e3) + " mm deep) never comes within " +
                         std::to_string(reach0 * 1e3) + " mm of any tissue particle (" + std::to_string(gap * 1e3) +
                         " mm from the tissue's bounding box)");
  }
  nd.halo = h_near;
  const double auto_r = 1.0 * h_near;
  nd.Rc = spec.cutting_radius > 0 ? spec.cutting_radius : auto_r;
  nd.Rf = spec.friction_radius > 0 ? spec.friction_radius : auto_r;
  nd.notch_radius = spec.gun && spec.gun->notch_radius > 0 ? spec.gun->notch_radius : nd.Rf;
  const double reach = std::max({nd.Rc, nd.Rf, nd.notch_radius}) + nd.halo + spec.plan_margin;
  for (const auto& [t, p] : cand) {
    if (segment_distance(S - reach * d0, d0, max_depth + 2 * reach, m.rest_pos[p]) > reach) continue;
    nd.plan_t.push_back(t);
    nd.plan_idx.push_back(p);
    m_min = std::min(m_min, m.mass[p]);
  }
  {
    std::vector<size_t> order(nd.plan_t.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return nd.plan_t[a] < nd.plan_t[b]; });
    std::vector<double> t2;
    std::vector<int> i2;
    for (size_t k : order) { t2.push_back(nd.plan_t[k]); i2.push_back(nd.plan_idx[k]); }
    nd.plan_t.swap(t2);
    nd.plan_idx.swap(i2);
  }
  if (nd.Rf < 0.87 * h_near)
    warnings.push_back("needle '" + spec.name + "': friction radius " + std::to_string(nd.Rf * 1e3) +
                        " mm is below 0.87 x the tissue spacing " + std::to_string(h_near * 1e3) +
                        " mm: some nodes inside tissue will find no particle in their zone");

  size_needle_buffers(nd, m, mf);
  if (!spec.guide.empty()) {
    // in the probe's guide: start / direction are the guide at the probe's start pose
    // (build_scene); attach_probe makes the needle follow it
    nd.guided = true;
    nd.interactive = spec.script.empty();  // a scenario script drives its depth along the guide until a live command
    nd.guide_now = nd.guide_prev = NeedlePath{spec.start, spec.direction};
    nd.h_sub = h_sub;
    nd.plan_reach = reach;
    nd.plan_scratch.reserve(n);
    nd.plan_t.reserve(n);
    nd.plan_idx.reserve(n);
    if (spec.gun) {
      nd.cores_done.resize(kMaxGuideCores);
      for (CoreState& c : nd.cores_done) {
        c.particles.reserve(kCoreCapacity);
        c.tumour_pos.reserve(kCoreCapacity);
        c.tumour_half.reserve(kCoreCapacity);
        c.per_component.assign(nc, 0);
        c.per_tag.assign(m.tag_names.size(), 0);
      }
    }
  }
  Vec3 v0;
  needle_command(nd, 0.0, nd.T, nd.d, v0);
  // a needle that starts inside a membrane component has already entered it
  for (int c = 0; c < nc; ++c)
    if (puncture_kc[c] > 0.0 && !mf.sheet[c] && m.components[c].surface >= 0 &&
        inside_rest_surface(m, m.surfaces[m.components[c].surface], nd.T))
      nd.entered[c] = 1;
  // a needle that starts in the lumen of a wall (in the probe's guide in the rectum) leaves it
  // through the wall: nothing touches it but the wall it presses until it is through
  for (int c = 0; c < nc && nd.lumen < 0; ++c)
    if (puncture_kc[c] > 0.0 && mf.sheet[c] && m.components[c].surface >= 0 &&
        inside_rest_surface(m, m.surfaces[m.components[c].surface], nd.T)) {
      nd.lumen = c;
      nd.in_lumen = true;
    }
  for (double depth : spec.seed_depths) {
    SeedState sd;
    sd.depth = depth;
    sd.planned = S + depth * d0;
    nd.seeds.push_back(sd);
  }
  nd.core.particles.reserve(kCoreCapacity);
  nd.core.tumour_pos.reserve(kCoreCapacity);
  nd.core.tumour_half.reserve(kCoreCapacity);
  nd.core.per_component.assign(nc, 0);
  nd.core.per_tag.assign(m.tag_names.size(), 0);
  resolve_tumour(nd, m);
  check_needle_stiffness(spec, m, h_sub, m_min, warnings);
  return nd_ptr;
}

}  // namespace ps
