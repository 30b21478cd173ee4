#include "engine/metrics/session_metrics.h"

#include <algorithm>
#include <cmath>

#include "engine/metrics/planned_sites.h"
#include "engine/model/role.h"
#include "engine/tools/needle/biopsy.h"
#include "engine/util/error.h"

namespace ps {

namespace {

enum : uint32_t { kUrethra = 1, kRectum = 2, kBladder = 4, kBone = 8, kCapsuleExit = 16, kLastStructure = kCapsuleExit };

// A component or tag the needle counts as tumour: one the needle lists (`tumour:`), else one
// whose role is lesion (as NeedleTool builds Needle::tumour, needle.cpp).
bool is_tumour(const std::string& n, Role role, const std::vector<std::string>& listed) {
  if (!listed.empty()) return std::find(listed.begin(), listed.end(), n) != listed.end();
  return role == Role::Lesion;
}

// Does particle p belong to tumour tissue as the needle's core would count it (biopsy.cpp)?
bool tumour_particle(const Model& m, int p, const std::vector<std::string>& listed) {
  const Component& c = m.components[m.component_of[p]];
  if (is_tumour(c.name, c.role, listed)) return true;
  if (m.particle_tags.empty()) return false;
  for (size_t t = 0; t < m.tag_names.size(); ++t)
    if ((m.particle_tags[p] >> t & 1u) && is_tumour(m.tag_names[t], m.tag_role(static_cast<int>(t)), listed)) return true;
  return false;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace

const char* structure_name(int bit) {
  switch (bit) {
    case kUrethra: return "urethra";
    case kRectum: return "rectal wall";
    case kBladder: return "bladder";
    case kBone: return "bone";
    case kCapsuleExit: return "capsule exit";
  }
  return "";
}

uint32_t structure_of(const Component& c) {
  switch (c.role) {
    case Role::Bone: return kBone;
    case Role::Urethra: return kUrethra;
    case Role::Rectum: return kRectum;
    case Role::Bladder: return kBladder;
    default: return 0;
  }
}

SessionMetrics::SessionMetrics(const Model& m, const NeedleTool& tool, const MetricsOptions& opt) : model_(&m), opt_(opt) {
  gland_ = m.find_organ(opt.gland, Role::Prostate);
  structure_of_.resize(m.components.size());
  for (size_t c = 0; c < m.components.size(); ++c) structure_of_[c] = static_cast<uint8_t>(structure_of(m.components[c]));
  tracks_.resize(tool.count());
  seed_sites_.resize(tool.count());
  for (int i = 0; i < tool.count(); ++i) {
    const NeedleSpec& sp = tool.spec(i);
    Track& t = tracks_[i];
    t.dir = sp.direction.normalized();
    t.gun = sp.gun.has_value();
    double planned = 0.0;  // deepest scripted depth (a brachytherapy needle ends withdrawn)
    for (const NeedleScriptPoint& q : sp.script) planned = std::max(planned, q.depth);
    if (t.gun) {
      t.sample_back = sp.gun->notch_offset + 0.5 * sp.gun->notch_length;
      planned += sp.gun->stroke - t.sample_back;
    }
    const Vec3 X = sp.target ? *sp.target : Vec3(sp.start + planned * t.dir);
    t.target = track_point(m, X);
    if (sp.target && t.target.component < 0)
      throw InputError(sp.file, sp.line, sp.key + ".target_mm", "the target lies outside every organ");
    if (t.target.anchor.valid()) t.lesion_target = tumour_particle(m, t.target.anchor.idx[0], sp.tumour);
    t.guided = !sp.guide.empty();
    if (!sp.planned_sites.empty()) {
      t.lesion_target = false;  // scored per lesion tag over its cores (finish)
      for (const PlannedSite& ps : planned_sites(m, sp.planned_sites))
        if (ps.particles > 0) t.sites.push_back(track_point(m, ps.centre));
      t.core_error.reserve(kMaxTrackedCores);
    }
    for (double d : sp.seed_depths) seed_sites_[i].push_back(track_point(m, sp.start + d * t.dir));
  }
  for (const Vec3& u : opt.urethra) urethra_.push_back(track_point(m, u));
  urethra_now_.resize(urethra_.size());
}

void SessionMetrics::observe(const NeedleTool& tool, const State& s) {
  auto hit = [&](Track& t, int component) {
    if (component >= 0) t.hit_mask |= structure_of_[component];
  };
  events_seen_ = tool.events().for_each_since(events_seen_, [&](const NeedleEvent& e) {
    if (e.needle < 0 || e.needle >= static_cast<int>(tracks_.size())) return;
    Track& t = tracks_[e.needle];
    switch (e.kind) {
      case NeedleEventKind::Contact:
        if (std::isnan(t.first_contact)) t.first_contact = e.time;
        if (std::isnan(first_contact_) || e.time < first_contact_) first_contact_ = e.time;
        if (t.entry < 0) t.entry = e.component;
        else if (e.component != t.entry) hit(t, e.component);
        break;
      case NeedleEventKind::Puncture:
        ++t.punctures;
        if (t.entry < 0) t.entry = e.component;
        if (e.component == t.entry) {
          if (++t.entry_punctures > 1) hit(t, e.component);
        } else {
          hit(t, e.component);
        }
        break;
      case NeedleEventKind::BoneHit: t.hit_mask |= kBone; break;
      case NeedleEventKind::Urethra: t.hit_mask |= kUrethra; break;
      case NeedleEventKind::GlandExit:
        t.hit_mask |= kCapsuleExit;
        ++t.gland_exits;
        break;
      case NeedleEventKind::Core: {
        const Vec3 dir = tool.readout(e.needle).direction;  // the needle's direction this tick
        if (!t.sites.empty() && static_cast<int>(t.core_error.size()) < kMaxTrackedCores) {
          const NeedleSpec& sp = tool.spec(e.needle);
          const Vec3 a = e.position - sp.gun->notch_offset * dir, b = a - sp.gun->notch_length * dir;
          double best = INFINITY;
          for (const TrackedPoint& site : t.sites) best = std::min(best, distance_to_segment(site.position(s.x), a, b));
          t.core_error.push_back(best);  // capacity reserved: no allocation
        }
        ++t.cores_seen;
        if (t.guided) t.entry_punctures = 0;  // the next pass goes through the rectal wall again
        if (t.gun && !t.decisive) {
          t.decisive = true;
          t.decisive_time = e.time;
          t.sample = e.position - t.sample_back * (t.guided ? dir : t.dir);
          t.target_now = t.target.position(s.x);
        }
        if (t.guided) t.decisive_time = e.time;  // the last core ends the procedure
        break;
      }
      case NeedleEventKind::Seed: t.last_seed_time = e.time; break;
      default: break;
    }
  });
  bool urethra_ready = false;
  for (int i = 0; i < static_cast<int>(tracks_.size()); ++i) {
    Track& t = tracks_[i];
    const NeedleReadout& r = tool.readout(i);
    if (r.contacted) {
      if (std::isnan(t.first_contact)) t.first_contact = s.time;
      if (std::isnan(first_contact_) || s.time < first_contact_) first_contact_ = s.time;
      t.peak_force = std::max(t.peak_force, r.axial_force_tick);
      t.force_sum += r.axial_force_tick;
      ++t.force_ticks;
    }
    // re-insertion: direction of travel along the planned line, with kReinsertStroke hysteresis
    const double d = r.plan_depth;
    if (t.forward) {
      if (d > t.extreme) t.extreme = d;
      else if (t.extreme - d > kReinsertStroke) { t.forward = false; t.extreme = d; }
    } else {
      if (d < t.extreme) t.extreme = d;
      else if (d - t.extreme > kReinsertStroke) {
        t.forward = true;
        t.extreme = d;
        // in the guide, a push after a core is the next core
        if (!std::isnan(t.first_contact) && !(t.guided && t.cores_seen > t.cores_at_forward)) ++t.reinsertions;
        t.cores_at_forward = t.cores_seen;
      }
    }
    if (!t.gun && r.contacted && d > t.best_depth) {
      t.best_depth = d;
      t.decisive = true;
      t.decisive_time = s.time;
      t.sample = r.tip;
      t.target_now = t.target.position(s.x);
    }
    if (r.contacted && !urethra_.empty()) {
      if (!urethra_ready) {
        for (size_t k = 0; k < urethra_.size(); ++k) urethra_now_[k] = urethra_[k].position(s.x);
        urethra_ready = true;
      }
      for (size_t k = 0; k + 1 < urethra_now_.size(); ++k)
        if (segment_distance(r.tip, urethra_now_[k], urethra_now_[k + 1]) < opt_.urethra_radius) { t.hit_mask |= kUrethra; break; }
    }
  }
}

void SessionMetrics::observe_probe(double force, double dt) {
  probe_peak_ = std::isnan(probe_peak_) ? force : std::max(probe_peak_, force);
  if (force > kProbeForceThreshold) probe_above_ += dt;
}

SessionReport SessionMetrics::finish(const NeedleTool& tool, const State& s, bool faulted) const {
  const Model& m = *model_;
  SessionReport rep;
  rep.scenario = m.name;
  rep.duration = s.time;
  rep.faulted = faulted;
  rep.probe_peak_force = probe_peak_;
  rep.probe_time_above = std::isnan(probe_peak_) ? NAN : probe_above_;
  double last = NAN;
  double err_sum = 0.0;
  int scored = 0;
  for (int i = 0; i < tool.count(); ++i) {
    const Track& t = tracks_[i];
    const NeedleSpec& sp = tool.spec(i);
    NeedleMetrics n;
    n.name = sp.name;
    n.target_rest = t.target.rest;
    n.punctures = t.punctures;
    n.reinsertions = t.reinsertions;
    n.peak_force = t.peak_force;
    n.mean_force = t.force_ticks > 0 ? t.force_sum / static_cast<double>(t.force_ticks) : 0.0;
    n.first_contact = t.first_contact;
    n.target_in_lesion = t.lesion_target;
    n.capsule_exits = t.gland_exits;
    for (uint32_t b = 1; b <= kLastStructure; b <<= 1)
      if (t.hit_mask & b) n.structures_hit.push_back(structure_name(static_cast<int>(b)));
    if (t.decisive) {
      n.scored = true;
      n.measured_at = t.gun ? "core" : "deepest";
      n.sample = t.sample;
      n.target_now = t.target_now;
      const Vec3 e = t.sample - t.target_now;
      n.error = e.norm();
      n.depth_error = e.dot(t.dir);
      n.lateral_error = (e - n.depth_error * t.dir).norm();
      if (!t.core_error.empty()) {  // planned sites: each core's notch against its site's centre
        double sum = 0.0;
        for (double ce : t.core_error) sum += ce;
        n.measured_at = "planned sites";
        n.error = sum / static_cast<double>(t.core_error.size());
        n.lateral_error = n.depth_error = NAN;
      }
      double end = t.decisive_time;
      if (!std::isnan(t.last_seed_time)) end = std::max(end, t.last_seed_time);
      n.insertion_time = end - t.first_contact;
      last = std::isnan(last) ? end : std::max(last, end);
      err_sum += n.error;
      ++scored;
      rep.max_error = std::isnan(rep.max_error) ? n.error : std::max(rep.max_error, n.error);
    }
    rep.structures_hit += static_cast<int>(n.structures_hit.size()) - ((t.hit_mask & kCapsuleExit) ? 1 : 0);
    rep.capsule_exits += n.capsule_exits;
    rep.reinsertions += n.reinsertions;
    rep.punctures += n.punctures;
    rep.needles.push_back(std::move(n));
  }
  if (scored > 0) rep.mean_error = err_sum / scored;
  if (!std::isnan(last) && !std::isnan(first_contact_)) rep.procedure_time = last - first_contact_;

  // biopsy
  for (int i = 0; i < tool.count(); ++i) {
    const NeedleSpec& sp = tool.spec(i);
    if (!sp.planned_site.empty() && std::find(rep.planned_sites.begin(), rep.planned_sites.end(), sp.planned_site) == rep.planned_sites.end())
      rep.planned_sites.push_back(sp.planned_site);
    for (const std::string& ps : sp.planned_sites)
      if (std::find(rep.planned_sites.begin(), rep.planned_sites.end(), ps) == rep.planned_sites.end()) rep.planned_sites.push_back(ps);
    if (!sp.gun) continue;
    std::vector<CoreReport> list = tool.cores(i);
    if (list.empty()) list.push_back(tool.core(i));  // not taken: listed as such
    bool lesion_hit = false;
    std::vector<std::string> lesion_tags_hit;
    for (size_t k = 0; k < list.size(); ++k) {
      const CoreReport& c = list[k];
      CoreMetrics cm;
      cm.needle = sp.name;
      cm.planned_site = sp.planned_site;
      cm.taken = c.taken;
      cm.time = c.time;
      cm.lesion_hit = c.tumour_particles > 0;
      cm.lesion_length = c.tumour_length;
      cm.notch_length = c.notch_length;
      cm.notch_centre = c.notch_centre;
      if (k < tracks_[i].core_error.size()) cm.site_error = tracks_[i].core_error[k];
      lesion_hit |= cm.lesion_hit;
      if (c.taken) {
        const CoreSite site = core_site(c);
        cm.site = site.label;
        for (const auto& [tag, count] : site.lesions)
          if (m.tag_role(m.find_tag(tag)) == Role::Lesion && std::find(lesion_tags_hit.begin(), lesion_tags_hit.end(), tag) == lesion_tags_hit.end())
            lesion_tags_hit.push_back(tag);
        if (cm.site.empty()) ++rep.cores_outside_gland;
        const std::string key = cm.site.empty() ? "outside the gland" : cm.site;
        auto it = std::find_if(rep.cores_per_zone.begin(), rep.cores_per_zone.end(), [&](const auto& z) { return z.first == key; });
        if (it == rep.cores_per_zone.end()) rep.cores_per_zone.emplace_back(key, 1);
        else ++it->second;
      }
      rep.cores.push_back(std::move(cm));
    }
    if (tracks_[i].lesion_target) {
      ++rep.lesions_targeted;
      if (!lesion_hit) ++rep.lesions_missed;
    }
    if (!sp.planned_sites.empty())  // every lesion of the case is a target of the protocol
      for (size_t t = 0; t < m.tag_names.size(); ++t)
        if (const std::string& tag = m.tag_names[t]; m.tag_role(static_cast<int>(t)) == Role::Lesion) {
          ++rep.lesions_targeted;
          if (std::find(lesion_tags_hit.begin(), lesion_tags_hit.end(), tag) == lesion_tags_hit.end()) ++rep.lesions_missed;
        }
  }
  for (const PlannedSite& ps : planned_sites(m, rep.planned_sites))
    if (ps.particles > 0) rep.planned_site_centres.push_back(ps);
  if (!rep.planned_sites.empty()) {
    int covered = 0;
    for (const std::string& p : rep.planned_sites)
      for (const CoreMetrics& c : rep.cores)
        if (c.taken && c.site.rfind(p, 0) == 0) { ++covered; break; }
    rep.coverage = static_cast<double>(covered) / static_cast<double>(rep.planned_sites.size());
  }

  // brachytherapy
  const Surface* gland = gland_ >= 0 && m.components[gland_].surface >= 0 ? &m.surfaces[m.components[gland_].surface] : nullptr;
  rep.gland_known = gland != nullptr;
  double seed_sum = 0.0;
  int deposited = 0;
  for (const SeedReport& sr : tool.seeds()) {
    SeedMetrics sm;
    sm.needle = tool.spec(sr.needle).name;
    sm.index = sr.index;
    sm.deposited = sr.deposited;
    if (sr.deposited) {
      sm.error = (sr.current - seed_sites_[sr.needle][sr.index].position(s.x)).norm();
      sm.outside_gland = gland && winding_number(*gland, s.x, sr.current) < 0.5;
      rep.seeds_outside_gland += sm.outside_gland;
      seed_sum += sm.error;
      ++deposited;
      rep.seed_error_max = std::isnan(rep.seed_error_max) ? sm.error : std::max(rep.seed_error_max, sm.error);
    }
    rep.seeds.push_back(std::move(sm));
  }
  if (deposited > 0) rep.seed_error_mean = seed_sum / deposited;
  // TG-43U1 dose of the seeds where the tissue carried them, beside the plan
  std::vector<Vec3> urethra_rest, urethra_now;
  for (const TrackedPoint& u : urethra_) {
    urethra_rest.push_back(u.rest);
    urethra_now.push_back(u.position(s.x));
  }
  DosimetryOptions dopt = opt_.dosimetry;
  dopt.gland = opt_.gland;
  rep.dosimetry = implant_dosimetry(m, s.x, tool, urethra_rest, urethra_now, dopt);
  return rep;
}

}  // namespace ps
