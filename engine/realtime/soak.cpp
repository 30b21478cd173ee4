#include "engine/realtime/soak.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "engine/realtime/lockstep.h"
#include "engine/util/error.h"

namespace ps {

LoopingPlayer::LoopingPlayer(std::vector<Command> cmds, int64_t period) : cmds_(std::move(cmds)), period_(period) {
  int64_t last = -1;
  for (const Command& c : cmds_) {
    if (c.tick < last) throw std::logic_error("LoopingPlayer: commands not sorted by tick");
    last = c.tick;
  }
  // A command at or past the period would come after the next cycle's first ones: stretch the
  // period so every cycle keeps the script's order.
  period_ = std::max<int64_t>({period_, last + 1, 1});
}

void LoopingPlayer::poll(int64_t tick, const Simulation&, CommandApplier& apply) {
  if (cmds_.empty()) return;
  for (;;) {
    if (next_ == cmds_.size()) {
      next_ = 0;
      ++cycle_;
    }
    const int64_t due = cmds_[next_].tick + cycle_ * period_;
    if (due > tick) return;
    Command c = cmds_[next_++];
    c.tick = due;
    apply.apply(c, tick);
  }
}

void LoopingPlayer::seek(int64_t tick) {
  cycle_ = tick / period_;
  next_ = 0;
  while (next_ < cmds_.size() && cmds_[next_].tick + cycle_ * period_ < tick) ++next_;
}

namespace {

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// max and RMS of |a - b| over the particles [m]
void compare(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double& mx, double& rms, int& at) {
  double mx2 = 0.0, sum = 0.0;
  at = -1;
  for (size_t p = 0; p < a.size(); ++p) {
    const double d2 = (a[p] - b[p]).squaredNorm();
    sum += d2;
    if (d2 > mx2) { mx2 = d2; at = static_cast<int>(p); }
  }
  mx = std::sqrt(mx2);
  rms = a.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(a.size()));
}

}  // namespace

SoakReport run_soak(Scene& scene, const Script* script, const SoakOptions& opt,
                    const std::function<void(const SoakReport&)>& progress, const SoakCheckpoint* resume) {
  using Clock = std::chrono::steady_clock;
  const Model& m = *scene.model;
  SoakReport r;
  r.target_ticks = std::max<int64_t>(1, std::llround(opt.duration / m.dt));
  std::unique_ptr<LoopingPlayer> player;
  if (script) {
    const double len = script->duration > 0 ? script->duration
                                            : (script->entries.empty() ? m.dt : script->entries.back().t + m.dt);
    player = std::make_unique<LoopingPlayer>(script_commands(*script, scene), std::max<int64_t>(1, std::llround(len / m.dt)));
    r.period_ticks = player->period();
  } else {
    r.period_ticks = std::max<int64_t>(1, std::llround(opt.period / m.dt));
  }
  LockstepRunner run(*scene.sim);
  if (player) run.add_source(player.get());
  const Watchdog dog(m, opt.limits);
  const double quiet_from = scripted_motion_end(scene.spec);  // [s]
  std::vector<Vec3> first_cycle_end;
  // a resumed soak: the state, and the figures and time spent so far
  double wall0 = 0.0, cpu0 = 0.0;
  int64_t applied0 = 0, refused0 = 0;
  if (resume) {
    if (resume->report.period_ticks != r.period_ticks)
      throw InputError(resume->state.file, 3, "period_ticks",
                       "the checkpoint's soak cycled every " + std::to_string(resume->report.period_ticks) + " ticks, this one every " +
                           std::to_string(r.period_ticks) + " (another script)");
    run.runner().load_state(resume->state);
    const int64_t target = r.target_ticks, period = r.period_ticks;
    r = resume->report;
    r.held = true;  // a checkpoint is only taken while the soak holds; its sitting may have timed out
    r.timeout = false;
    r.fault.clear();
    r.end_volume_drift.clear();
    r.target_ticks = target;
    r.period_ticks = period;
    wall0 = r.wall_s;
    cpu0 = r.cpu_s;
    applied0 = r.applied;
    refused0 = r.refused;
    first_cycle_end = resume->first_cycle_end;
  }
  r.limits = dog.limits();  // the effective limits (leave margin: the scene's unless given)
  r.kinetic_limit = dog.max_kinetic();
  const auto w0 = Clock::now();
  const double c0 = cpu_seconds();
  auto last_report = w0, last_checkpoint = w0;
  auto update_times = [&] {
    r.ticks = run.tick();
    r.sim_s = scene.sim->state().time;
    r.wall_s = wall0 + std::chrono::duration<double>(Clock::now() - w0).count();
    r.cpu_s = cpu0 + cpu_seconds() - c0;
    r.applied = applied0 + run.applier().applied();
    r.refused = refused0 + run.applier().refused();
  };
  SoakCheckpoint cp;
  auto checkpoint = [&] {
    update_times();
    run.runner().current_state(cp.state);
    cp.report = r;
    cp.first_cycle_end = first_cycle_end;
    opt.checkpoint(cp);
  };
  while (run.tick() < r.target_ticks) {
    if (!run.step()) {
      r.held = false;
      r.fault = run.runner().fault_text();
      break;
    }
    const State& s = scene.sim->state();
    const WatchFinding f = dog.check(m, s, &r.peaks);
    if (!f.ok) {
      r.held = false;
      r.fault = "tick " + std::to_string(run.tick() - 1) + ": watchdog: " + f.describe(m);
      break;
    }
    if (run.tick() % r.period_ticks == 0) {  // end of a cycle
      ++r.cycles;
      if (r.cycles == 1) {
        first_cycle_end = s.x;
        r.cycle_end_kinetic_first = kinetic_energy(m, s);
      } else {
        compare(s.x, first_cycle_end, r.cycle_drift_max, r.cycle_drift_rms, r.cycle_drift_particle);
      }
      r.cycle_end_kinetic_last = kinetic_energy(m, s);
      const double kinetic = r.cycle_end_kinetic_last;
      if (r.ring_base_cycle == 0 && s.time >= quiet_from - 0.5 * m.dt) {
        r.ring_base_cycle = r.cycles;
        r.ring_base_kinetic = kinetic;
      } else if (r.ring_base_cycle > 0 && opt.ring_factor > 0 &&
                 !(kinetic <= opt.ring_factor * r.ring_base_kinetic + opt.ring_floor_j)) {
        int fastest = 0;
        for (int p = 1; p < m.particle_count(); ++p)
          if (s.v[p].squaredNorm() > s.v[fastest].squaredNorm()) fastest = p;
        const int c = m.component_of[fastest];
        char b[384];
        std::snprintf(b, sizeof b,
                      "tick %lld: self-excited oscillation: kinetic energy %.3g J at the end of cycle %lld (t=%.6g s), more than "
                      "%.3g x the %.3g J at the end of cycle %lld + %.3g J; fastest particle %d (%s) at %.3g m/s",
                      static_cast<long long>(run.tick() - 1), kinetic, static_cast<long long>(r.cycles), s.time,
                      opt.ring_factor, r.ring_base_kinetic, static_cast<long long>(r.ring_base_cycle), opt.ring_floor_j, fastest,
                      c >= 0 ? m.components[c].name.c_str() : "?", s.v[fastest].norm());
        r.held = false;
        r.fault = b;
        break;
      }
    }
    if ((run.tick() & 63) == 0) {
      const auto now = Clock::now();
      const double wall = std::chrono::duration<double>(now - w0).count();
      if (opt.budget_s > 0 && wall > opt.budget_s) {
        r.timeout = true;
        break;
      }
      if (progress && std::chrono::duration<double>(now - last_report).count() >= opt.report_every_s) {
        last_report = now;
        update_times();
        progress(r);
      }
      if (opt.checkpoint && std::chrono::duration<double>(now - last_checkpoint).count() >= opt.checkpoint_every_s) {
        last_checkpoint = now;
        checkpoint();
      }
    }
  }
  update_times();
  // the end, or the wall budget's: a longer soak, or the rest of this one, can go on from it
  if (opt.checkpoint && r.held) checkpoint();
  const State& s = scene.sim->state();
  for (size_t si = 0; si < m.surfaces.size(); ++si) {
    const Surface& surf = m.surfaces[si];
    if (!surf.volume_constrained || !(s.target_volume[si] > 0)) continue;
    double vol = 0.0;
    for (const auto& t : surf.faces) vol += s.x[t[0]].dot(s.x[t[1]].cross(s.x[t[2]])) / 6.0;
    r.end_volume_drift.emplace_back(m.components[surf.component].name, std::abs(vol - s.target_volume[si]) / s.target_volume[si]);
  }
  return r;
}

double scripted_motion_end(const ScenarioSpec& spec) {
  double end = 0.0;
  for (const NeedleSpec& n : spec.needles.needles) {
    if (!n.script.empty()) end = std::max(end, n.script.back().t);
    if (n.gun && std::isfinite(n.gun->fire_time)) end = std::max(end, n.gun->fire_time + n.gun->duration + n.gun->settle);
  }
  if (spec.probe)
    for (const ProbeMoveSpec& mv : spec.probe->moves) end = std::max(end, mv.t1);
  if (spec.filling)
    for (const FillSpec& f : spec.filling->schedule) end = std::max(end, f.t1);
  return end;
}

std::string soak_figures(const SoakReport& r, const Model& m) {
  const WatchPeaks& p = r.peaks;
  const std::string worst = p.worst_surface >= 0 && p.worst_surface < static_cast<int>(m.surfaces.size())
                                ? m.components[m.surfaces[p.worst_surface].component].name
                                : std::string("-");
  auto who = [&](int i) {
    if (i < 0 || i >= m.particle_count()) return std::string("-");
    const int c = m.component_of[i];
    return "particle " + std::to_string(i) + " (" + (c >= 0 ? m.components[c].name : std::string("?")) + ")";
  };
  char b[768];
  std::snprintf(b, sizeof b,
                "%.6g s simulated (%lld ticks, %.0f s CPU), %lld cycles of %.4g s, %lld commands applied, %lld refused; "
                "peak speed %.3g m/s at t=%.4g s, %s (limit %.3g); peak kinetic energy %.3g J at t=%.4g s (limit %.3g J); "
                "worst volume drift %.3g (%s, t=%.4g s; limit %.3g); largest displacement from rest %.2f mm, %s; "
                "closest to leaving the scene %.1f mm inside the box",
                r.sim_s, static_cast<long long>(r.ticks), r.cpu_s, static_cast<long long>(r.cycles), r.period_ticks * m.dt,
                static_cast<long long>(r.applied), static_cast<long long>(r.refused), p.max_speed, p.max_speed_time,
                who(p.fastest).c_str(), r.limits.max_speed, p.max_kinetic, p.max_kinetic_time, r.kinetic_limit, p.max_volume_drift, worst.c_str(),
                p.max_volume_drift_time, r.limits.volume_drift, p.max_displacement * 1e3,
                who(p.farthest).c_str(), (p.min_margin < 1e299 ? p.min_margin : 0.0) * 1e3);
  std::string out = b;
  if (r.cycles >= 2) {
    std::snprintf(b, sizeof b,
                  "; cycle drift (end of cycle %lld vs end of cycle 1) max %.4g mm (%s), RMS %.4g mm; kinetic energy at the end "
                  "of cycle 1 %.3g J, of cycle %lld %.3g J",
                  static_cast<long long>(r.cycles), r.cycle_drift_max * 1e3, who(r.cycle_drift_particle).c_str(), r.cycle_drift_rms * 1e3,
                  r.cycle_end_kinetic_first, static_cast<long long>(r.cycles), r.cycle_end_kinetic_last);
    out += b;
  } else {
    out += "; cycle drift: fewer than 2 cycles";
  }
  return out;
}

}  // namespace ps
