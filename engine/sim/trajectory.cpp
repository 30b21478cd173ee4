#include "engine/sim/trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/sim/run.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/tool_kind.h"

namespace ps {

Trajectory record_trajectory(const ScenarioSpec& spec, std::shared_ptr<const Model> model, double duration,
                             const Vec3& target_point) {
  const Model& m = *model;
  Simulation sim(model);
  NeedleTool* needles = add_scenario_tools(spec, model, sim).as<NeedleTool>();

  Trajectory tr;
  tr.dt = m.dt;
  tr.substeps = m.substeps;
  const int prostate = m.find_role(Role::Prostate);
  if (prostate >= 0) {
    const Component& c = m.components[prostate];
    for (int p = c.first_particle; p < c.first_particle + c.particle_count; ++p) tr.watched_particles.push_back(p);
  }
  tr.prostate_count = static_cast<int>(tr.watched_particles.size());
  int best = 0;
  for (int p = 1; p < m.particle_count(); ++p)
    if ((m.rest_pos[p] - target_point).squaredNorm() < (m.rest_pos[best] - target_point).squaredNorm()) best = p;
  tr.target = best;
  tr.watched_particles.push_back(best);

  const long ticks = std::lround(duration / m.dt);
  int64_t seen_events = 0;  // events pushed so far (total, so a wrapped ring is handled)
  double contact_depth = -1.0;
  double evaluated = 0.0;  // sum over ticks of the evaluated fraction of the tet elements
  for (long k = 0; k < ticks; ++k) {
    if (!sim.tick()) {
      tr.faulted = true;
      tr.fault = sim.state().fault.describe(m);
      break;
    }
    const State& s = sim.state();
    std::vector<Vec3> w;
    w.reserve(tr.watched_particles.size());
    for (int p : tr.watched_particles) w.push_back(s.x[p]);
    tr.watched.push_back(std::move(w));
    if (m.sleep.enabled() && m.tets.count() > 0) evaluated += static_cast<double>(s.tet_awake_count) / m.tets.count();
    else evaluated += 1.0;
    for (const Surface& surf : m.surfaces)
      if (surf.volume_constrained) {
        const auto err = volume_errors(m, s);
        for (const auto& [name, e] : err)
          if (m.surfaces[m.components[m.find_component(name)].surface].volume_constrained)
            tr.worst_volume_error = std::max(tr.worst_volume_error, e);
        break;
      }
    if (needles && needles->count() > 0) {
      const NeedleReadout& r = needles->readout(0);
      tr.force.push_back(r.axial_force_tick);
      tr.tip_depth.push_back(r.plan_depth);
      if (r.contacted && contact_depth < 0) contact_depth = r.plan_depth;
      const NeedleEventRing& ring = needles->events();
      const int64_t fresh = ring.total() - seen_events;
      const auto events = fresh > 0 ? ring.snapshot() : std::vector<NeedleEvent>{};
      const size_t from = events.size() - static_cast<size_t>(std::min<int64_t>(fresh, events.size()));
      for (size_t e = from; e < events.size(); ++e) {
        const NeedleEvent& ev = events[e];
        if (ev.kind != NeedleEventKind::Puncture) continue;
        tr.punctures.push_back(PunctureRecord{ev.needle, ev.component, ev.time,
                                              (ev.position - spec.needles.needles[ev.needle].start)
                                                  .dot(spec.needles.needles[ev.needle].direction.normalized()),
                                              ev.force});
        if (ev.needle == 0 && tr.punctures.size() == 1 && contact_depth >= 0)
          tr.max_tenting = std::max(tr.max_tenting, tr.punctures.back().depth - contact_depth);
      }
      seen_events = ring.total();
    }
  }
  if (!tr.watched.empty()) tr.evaluated_elements = evaluated / static_cast<double>(tr.watched.size());
  return tr;
}

TrajectoryError compare_trajectories(const Trajectory& run, const Trajectory& ref) {
  TrajectoryError e;
  // a run whose tick is a whole multiple r of the reference's is compared at its own ticks' ends
  // (reference tick (k + 1) r - 1), its tick-average force against the mean of the r reference ticks
  const double ratio = ref.dt > 0.0 ? run.dt / ref.dt : 1.0;
  const size_t r = std::max<long>(1, std::lround(ratio));
  if (std::abs(ratio - static_cast<double>(r)) > 1e-9 * ratio)
    throw std::invalid_argument("compare_trajectories: the run's tick is not a whole multiple of the reference's");
  const size_t n = std::min(run.watched.size(), ref.watched.size() / r);
  double f2 = 0.0;
  const size_t nf = std::min(run.force.size(), ref.force.size() / r);
  for (size_t k = 0; k < nf; ++k) {
    double fr = 0.0;
    for (size_t j = 0; j < r; ++j) fr += ref.force[k * r + j];
    fr /= static_cast<double>(r);
    f2 += (run.force[k] - fr) * (run.force[k] - fr);
  }
  for (double f : ref.force) e.force_peak = std::max(e.force_peak, std::abs(f));
  e.force_rms = nf ? std::sqrt(f2 / nf) : 0.0;
  for (size_t k = 0; k < n; ++k) {
    const std::vector<Vec3>& rw = ref.watched[(k + 1) * r - 1];
    double s2 = 0.0;
    for (int i = 0; i < run.prostate_count; ++i) {
      const double d = (run.watched[k][i] - rw[i]).norm();
      s2 += d * d;
      e.prostate_max = std::max(e.prostate_max, d);
    }
    if (run.prostate_count > 0) e.prostate_rms = std::max(e.prostate_rms, std::sqrt(s2 / run.prostate_count));
    e.target = std::max(e.target, (run.watched[k].back() - rw.back()).norm());
  }
  // punctures matched in order per (needle, component)
  std::vector<bool> used(ref.punctures.size(), false);
  for (const PunctureRecord& p : run.punctures) {
    bool found = false;
    for (size_t j = 0; j < ref.punctures.size() && !found; ++j)
      if (!used[j] && ref.punctures[j].needle == p.needle && ref.punctures[j].component == p.component) {
        used[j] = found = true;
        e.puncture_depth = std::max(e.puncture_depth, std::abs(p.depth - ref.punctures[j].depth));
      }
    if (!found) ++e.puncture_mismatch;
  }
  for (bool u : used) e.puncture_mismatch += u ? 0 : 1;
  e.volume = run.worst_volume_error;
  return e;
}

}  // namespace ps
