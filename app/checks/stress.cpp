#include "app/checks/stress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>

#include "engine/realtime/command_apply.h"
#include "engine/realtime/command_queue.h"
#include "engine/realtime/script.h"
#include "engine/realtime/soak.h"
#include "engine/realtime/soak_checkpoint.h"
#include "engine/scenario/compile.h"
#include "engine/sim/watchdog.h"
#include "engine/step/simulation.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/tools/tool_kind.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {

using Clock = std::chrono::steady_clock;

// Formats up to four doubles (every conversion in `f` must be a floating one: %g, %.3g, %f).
std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

// A compiled scene with its instruments, as `simulate` builds it.
struct Scene {
  std::shared_ptr<const Model> model;
  std::unique_ptr<Simulation> sim;
  ProbeTool* probe = nullptr;
  FillingTool* filling = nullptr;
};

Scene build(const ScenarioSpec& spec, std::shared_ptr<const Model> model = nullptr) {
  Scene s;
  s.model = model ? model : compile_scenario(spec);
  s.sim = std::make_unique<Simulation>(s.model);
  const ToolSet tools = add_scenario_tools(spec, s.model, *s.sim);  // every kind the scenario has, connected
  s.probe = tools.as<ProbeTool>();
  s.filling = tools.as<FillingTool>();
  return s;
}

struct Outcome {
  bool held = true, timeout = false;
  std::string finding;
  double sim_s = 0.0, wall_s = 0.0;
};

// Runs `seconds` of simulated time tick by tick under the watchdog and the wall budget.
// substep > 0 replaces the scene's substep [s] (the tick is split into round(dt / substep) steps).
// before_tick(tick) runs between ticks (commands, impulses).
Outcome run_watched(Scene& sc, double seconds, double budget_s, double substep = 0.0,
                    const std::function<void(int64_t)>& before_tick = {}) {
  const Model& m = *sc.model;
  const Watchdog dog(m);
  Outcome o;
  const auto t0 = Clock::now();
  const int64_t ticks = std::max<int64_t>(1, std::llround(seconds / m.dt));
  const int n = substep > 0 ? std::max(1, static_cast<int>(std::lround(m.dt / substep))) : m.substeps;
  for (int64_t k = 0; k < ticks; ++k) {
    if (before_tick) before_tick(k);
    bool ok = true;
    for (int i = 0; i < n && ok; ++i) ok = sc.sim->step(m.dt / n);
    const WatchFinding f = dog.check(m, sc.sim->state());
    o.sim_s = sc.sim->state().time;
    if (!ok || !f.ok) {
      o.held = false;
      o.finding = f.ok ? sc.sim->state().fault.describe(m) : f.describe(m);
      break;
    }
    o.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (o.wall_s > budget_s) {
      o.timeout = true;
      o.finding = fmt("wall budget of %.0f s ran out at t=%.4g s of %.4g s", budget_s, o.sim_s, ticks * m.dt);
      break;
    }
  }
  o.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return o;
}

// Small seeded velocities on every free particle: excites every mode, so an unstable substep
// shows within a few hundred steps instead of waiting for round-off.
void perturb(Scene& sc, uint64_t seed, double speed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  State& s = sc.sim->state();
  for (int p = 0; p < sc.model->particle_count(); ++p)
    if (sc.model->inv_mass[p] > 0) s.v[p] += speed * Vec3(U(rng), U(rng), U(rng));
}

StressResult finish(StressResult r, const Outcome& o, const std::string& held_text) {
  r.sim_s = o.sim_s;
  r.wall_s = o.wall_s;
  if (o.timeout) {
    r.status = "TIMEOUT";
    r.held = o.finding;
  } else if (!o.held) {
    r.status = "FAIL";
    r.held = r.name + " failed: " + o.finding;
  } else {
    r.status = "held";
    r.held = held_text;
  }
  return r;
}

// --- cases -------------------------------------------------------------------------------------

StressResult stable_substep(const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0) {
  StressResult r{spec.name, "stable_substep"};
  Scene base = build(spec, m0);
  const Model& m = *base.model;
  const double shipped = m.dt / m.substeps;
  const double trial_s = opt.quick ? 0.01 : 0.04;
  const auto t0 = Clock::now();
  auto stable = [&](double h, std::string* why) {
    Scene sc = build(spec, base.model);
    perturb(sc, opt.seed, 1e-3);
    const double left = opt.budget_s - std::chrono::duration<double>(Clock::now() - t0).count();
    const Outcome o = run_watched(sc, trial_s, std::max(1.0, left), h);
    if (why) *why = o.finding;
    return o.held && !o.timeout;
  };
  std::string why;
  r.tried = fmt("substep h = f x shipped %.4g ms, f = 1, 1.5, 2, 3, 4, 6, 8, 12 then bisect; %.3g s each with 1 mm/s "
                "random velocities",
                shipped * 1e3, trial_s);
  if (!stable(shipped, &why)) {
    Outcome o;
    o.held = false;
    o.finding = "the shipped substep is unstable: " + why;
    return finish(r, o, "");
  }
  double good = 1.0, bad = 0.0;
  for (double f : {1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0}) {
    if (std::chrono::duration<double>(Clock::now() - t0).count() > opt.budget_s) break;
    if (stable(f * shipped, nullptr)) good = f;
    else { bad = f; break; }
  }
  for (int i = 0; i < (opt.quick ? 1 : 3) && bad > 0; ++i) {
    if (std::chrono::duration<double>(Clock::now() - t0).count() > opt.budget_s) break;
    const double mid = 0.5 * (good + bad);
    if (stable(mid * shipped, nullptr)) good = mid; else bad = mid;
  }
  Outcome o;
  o.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  o.sim_s = trial_s;
  return finish(r, o,
                fmt("largest stable substep %.4g ms = %.3g x shipped %.4g ms (estimate %.4g ms)", good * shipped * 1e3, good,
                    shipped * 1e3, m.stable_dt_estimate * 1e3) +
                    (bad > 0 ? fmt("; unstable at %.3g x", bad) : std::string("; stable at every factor tried")));
}

// The largest elastic component gets a sphere `ratio` times stiffer at its centroid.
StressResult stiff_inclusion(const ScenarioSpec& spec, const StressOptions& opt, double ratio, const Model& m0) {
  StressResult r{spec.name, fmt("stiff_inclusion_%g", ratio)};
  // A lesion-like inclusion in the prostate where the scene has one, else in the largest elastic
  // component (a bone-like inclusion in soft fat).
  int best = m0.find_role(Role::Prostate);
  if (best >= 0 && m0.components[best].kind != ComponentKind::Elastic) best = -1;
  for (size_t c = 0; c < m0.components.size() && m0.find_role(Role::Prostate) < 0; ++c)
    if (m0.components[c].kind == ComponentKind::Elastic &&
        (best < 0 || m0.components[c].particle_count > m0.components[best].particle_count))
      best = static_cast<int>(c);
  if (best < 0) return {spec.name, r.name, "no elastic component", "", "skipped"};
  const Component& comp = m0.components[best];
  Vec3 centre = Vec3::Zero();
  for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) centre += m0.rest_pos[p];
  centre /= comp.particle_count;
  const ComponentSpec* cs = nullptr;
  for (const auto& c : spec.components) if (c.name == comp.name) cs = &c;
  const MaterialSpec* mat = nullptr;
  for (const auto& x : spec.materials) if (cs && x.name == cs->material) mat = &x;
  if (!cs || !mat) return {spec.name, r.name, "component not in the spec", "", "skipped"};
  ScenarioSpec s = spec;
  OverrideSpec o;
  o.component = comp.name;
  o.region.kind = RegionSpec::Sphere;
  o.region.center = centre;
  o.region.radius = 1.5 * cs->spacing;  // a lesion-sized sphere holding a few particles
  if (mat->young) o.young = *mat->young * ratio;
  if (mat->k_e) o.k_e = *mat->k_e * ratio;
  o.loc = mat->loc;
  s.overrides.push_back(o);
  r.tried = fmt("sphere r = %.3g mm at the centroid of '", o.region.radius * 1e3) + comp.name +
            fmt("', %g:1 stiffer than the rest; %.3g s with 1 mm/s random velocities", ratio,
                                         opt.quick ? std::min(opt.run_s, 0.005) : opt.run_s);
  std::shared_ptr<const Model> model;
  try {
    model = compile_scenario(s);
  } catch (const InputError& e) {
    return {spec.name, r.name, r.tried, std::string("compile refused it cleanly: ") + e.what(), "refused"};
  }
  r.tried += fmt(" (compile raised substeps %g -> %g per tick)", static_cast<double>(m0.substeps),
                 static_cast<double>(model->substeps));
  Scene sc = build(s, model);
  perturb(sc, opt.seed, 1e-3);
  // The stiff sphere multiplies the substeps by up to sqrt(ratio): the quick run is shorter.
  const Outcome out = run_watched(sc, opt.quick ? std::min(opt.run_s, 0.005) : opt.run_s, opt.budget_s);
  return finish(r, out, fmt("no fault over %.3g s", out.sim_s));
}

StressResult needle_case(const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0, const std::string& which) {
  StressResult r{spec.name, which};
  if (spec.needles.needles.empty()) return {spec.name, which, "scene has no needle", "", "skipped"};
  ScenarioSpec s = spec;
  s.needles.needles.resize(1);
  NeedleSpec& n = s.needles.needles[0];
  n.seed_depths.clear();  // the stressed script no longer reaches the planned seed depths
  double run = opt.run_s;
  if (which == "needle_1m_s") {
    const double depth = opt.quick ? 0.03 : 0.06;  // [m]
    n.script = {{0.0, 0.0}, {depth / 1.0, depth}};
    n.gun.reset();
    run = depth + 0.01;
    r.tried = "needle '" + n.name + "' driven " + fmt("%.0f mm at 1 m/s, then held 10 ms", depth * 1e3);
  } else if (which == "gun_fired") {
    BiopsyGunSpec g = n.gun.value_or(BiopsyGunSpec{});
    g.fire_time = 0.005;
    n.gun = g;
    if (n.script.empty()) n.script = {{0.0, 0.0}};
    run = g.fire_time + g.duration + g.settle + 0.01;
    r.tried = "needle '" + n.name + "' gun fired at 5 ms: " + fmt("%.0f mm stroke in %.0f ms", g.stroke * 1e3, g.duration * 1e3);
  } else {  // pullback_stuck: in slowly so the shaft is held by friction, then out at 1 m/s
    const double depth = opt.quick ? 0.01 : 0.02, in = depth / 0.2;  // [m], [s] at 0.2 m/s
    n.script = {{0.0, 0.0}, {in, depth}, {in + 0.01, depth}, {in + 0.01 + depth / 1.0, 0.0}};
    n.gun.reset();
    run = in + 0.01 + depth + 0.01;
    r.tried = "needle '" + n.name + fmt("' in %.0f mm at 0.2 m/s, then pulled out at 1 m/s while stuck", depth * 1e3);
  }
  Scene sc = build(s, m0);
  const Outcome out = run_watched(sc, run, opt.budget_s);
  return finish(r, out, fmt("no fault over %.3g s", out.sim_s));
}

StressResult probe_case(const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0) {
  StressResult r{spec.name, "probe_push_rotate"};
  if (!spec.probe) return {spec.name, r.name, "scene has no probe", "", "skipped"};
  ScenarioSpec s = spec;
  s.probe->max_speed = 1.0;          // [m/s] far past the 0.05 m/s hand speed
  s.probe->max_angular_speed = 20.0; // [rad/s]
  Scene sc = build(s, m0);
  ProbePose target = s.probe->pose;
  target.insertion += 0.03;          // 30 mm deeper than the scene's pose
  target.roll += 1.5707963;          // quarter turn
  target.tilt = 0.2;
  const double run = opt.quick ? 0.05 : 0.1;
  r.tried = "probe pushed 30 mm past its pose, rolled 90 deg and tilted 11 deg in 30 ms (limits raised to 1 m/s, 20 rad/s)";
  bool first = true;
  const Outcome out = run_watched(sc, run, opt.budget_s, 0.0, [&](int64_t) {
    if (first) sc.probe->move_to(target, 0.03);
    first = false;
  });
  std::string reports;
  for (const auto& w : sc.probe->reports()) reports += (reports.empty() ? "; probe: " : " | ") + w;
  return finish(r, out, fmt("no fault over %.3g s", out.sim_s) + reports.substr(0, 200));
}

StressResult fill_case(const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0) {
  StressResult r{spec.name, "fill_max_rate"};
  if (!spec.filling || spec.filling->schedule.empty()) return {spec.name, r.name, "scene fills no organ", "", "skipped"};
  Scene sc = build(spec, m0);
  const std::string organ = spec.filling->schedule[0].component;
  const double rate = sc.filling->max_rate();
  const double run = opt.quick ? 0.1 : 0.5;
  r.tried = "'" + organ + fmt("' filled at the largest allowed rate %.3g ml/s for %.3g s", rate * 1e6, run);
  bool first = true;
  const Outcome out = run_watched(sc, run, opt.budget_s, 0.0, [&](int64_t) {
    if (first) sc.filling->set_rate(organ, rate);
    first = false;
  });
  return finish(r, out, fmt("no fault; target volume %.4g ml", sc.filling->target_volume(organ) * 1e6));
}

StressResult impulses(const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0) {
  StressResult r{spec.name, "random_impulses"};
  Scene sc = build(spec, m0);
  std::mt19937_64 rng(opt.seed * 7919 + 1);
  std::uniform_int_distribution<int> P(0, sc.model->particle_count() - 1);
  std::normal_distribution<double> N(0.0, 1.0);
  const double dv = 0.5;  // [m/s] a sharp knock on one particle
  r.tried = fmt("seed %g: every 5th tick one random particle gets a %.2g m/s kick; %.3g s", static_cast<double>(opt.seed), dv,
                opt.run_s);
  const Outcome out = run_watched(sc, opt.run_s, opt.budget_s, 0.0, [&](int64_t k) {
    if (k % 5) return;
    const int p = P(rng);
    if (sc.model->inv_mass[p] > 0) sc.sim->state().v[p] += dv * Vec3(N(rng), N(rng), N(rng)).normalized();
  });
  return finish(r, out, fmt("no fault over %.3g s", out.sim_s));
}

StressResult random_commands(const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0) {
  StressResult r{spec.name, "random_commands"};
  if (!spec.probe && !spec.filling) return {spec.name, r.name, "scene has no live-commanded instrument", "", "skipped"};
  Scene sc = build(spec, m0);
  CommandQueue queue(256);
  CommandApplier applier(*sc.sim);
  std::mt19937_64 rng(opt.seed * 104729 + 3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::uniform_int_distribution<int> K(0, 9);
  const int organ = spec.filling && !spec.filling->schedule.empty()
                        ? sc.model->find_component(spec.filling->schedule[0].component) : -1;
  int64_t pushed = 0;
  r.tried = fmt("seed %g: a random command every 10 ticks through CommandQueue/CommandApplier (probe poses within "
                "+-20 mm / +-0.6 rad, some NaN or beyond limits; fill rates +-2x the limit); %.3g s",
                static_cast<double>(opt.seed), opt.run_s);
  const Outcome out = run_watched(sc, opt.run_s, opt.budget_s, 0.0, [&](int64_t k) {
    if (k % 10 == 0) {
      Command c;
      c.tick = k;
      const int kind = K(rng);
      if (sc.probe && (kind < 6 || !sc.filling)) {
        const ProbePose& p = sc.probe->pose();
        c.kind = CommandKind::ProbeMove;
        c.probe.insertion = p.insertion + 0.02 * U(rng);
        for (int a = 0; a < 3; ++a) c.probe.offset[a] = p.offset[a] + 0.005 * U(rng);
        c.probe.roll = 0.6 * U(rng);
        c.probe.tilt = 0.6 * U(rng);
        c.probe.yaw = 0.6 * U(rng);
        c.probe.duration = 0.02 * (1 + U(rng));
        if (kind == 0) c.probe.tilt = std::nan("");   // must be refused, not applied
        if (kind == 1) c.probe.yaw = 2.0;             // beyond 45 degrees
      } else {
        c.kind = kind % 2 ? CommandKind::FillRate : CommandKind::FillTo;
        c.fill.component = kind == 9 ? 12345 : organ;  // an unknown organ must be refused
        c.fill.value = c.kind == CommandKind::FillRate ? 2.0 * U(rng) * sc.filling->max_rate()
                                                  : sc.filling->target_volume(spec.filling->schedule[0].component) * (1 + 0.1 * U(rng));
        c.fill.duration = 0.05;
      }
      if (queue.push(c)) ++pushed;
    }
    applier.apply_due(queue, k);
  });
  return finish(r, out, fmt("no fault; %g commands, %g applied, %g refused cleanly", static_cast<double>(pushed),
                            static_cast<double>(applier.applied()), static_cast<double>(applier.refused())));
}

StressResult soak(const ScenarioSpec& spec, const StressOptions& opt) {
  StressResult r{spec.name, "soak"};
  const std::string script_file = soak_script_for(spec, opt);
  std::unique_ptr<Script> script;
  if (!script_file.empty()) script = std::make_unique<Script>(parse_script_file(script_file));
  ps::Scene sc = build_scene(spec);  // the scene as `run` builds it (needle on the probe guide)
  if (!spec.file.empty()) sc.content_hash = file_content_hash(spec.file);
  SoakOptions so;
  so.duration = opt.soak_s;
  so.budget_s = opt.budget_s;
  so.report_every_s = opt.report_every_s;
  so.ring_floor_j = spec.rest_kinetic_energy;
  if (!opt.checkpoint.empty()) {
    so.checkpoint_every_s = opt.checkpoint_every_s;
    so.checkpoint = [&](const SoakCheckpoint& c) {
      SoakCheckpoint named = c;
      named.state.scenario = spec.name;
      named.state.scenario_hash = sc.content_hash;
      write_soak_checkpoint(opt.checkpoint, named, script_file);
      if (opt.progress)
        opt.progress(spec.name + fmt(" soak: checkpoint at t = %.6g s written to ", c.report.sim_s) + opt.checkpoint);
    };
  }
  if (opt.resume) check_state_matches(opt.resume->state, spec.name, sc.content_hash);
  r.tried = fmt("the scene for %.6g s of simulated time", opt.soak_s) +
            (script ? ", looping its script " + script_file + fmt(" (%.4g s a cycle)", script->duration)
                    : std::string(", no script (its own instrument scripts only)")) +
            fmt("; watchdog every tick: NaN, energy (10 m/s), volume drift 5%%, particles %g mm outside the scene",
                sc.model->leave_margin * 1e3) +
            fmt("; at each cycle's end: kinetic energy within %g x that at the first cycle end after the scene's own scripts + %g J "
                "(self-excitation)",
                so.ring_factor, so.ring_floor_j);
  const Model& m = *sc.model;
  const SoakReport rep = run_soak(sc, script.get(), so, [&](const SoakReport& p) {
    if (!opt.progress) return;
    const double eta = p.sim_s > 0 ? p.wall_s * (opt.soak_s - p.sim_s) / p.sim_s : 0.0;
    opt.progress(spec.name + fmt(" soak: t = %.5g s of %.5g s (%.2f%%), %.0f s wall", p.sim_s, opt.soak_s,
                                 100.0 * p.sim_s / opt.soak_s, p.wall_s) +
                 fmt(" (%.3g s simulated per CPU s, ETA %.0f s wall): ", p.sim_s / std::max(1e-9, p.cpu_s), eta) +
                 soak_figures(p, m));
  }, opt.resume.get());
  Outcome o;
  o.held = rep.held;
  o.timeout = rep.timeout;
  o.sim_s = rep.sim_s;
  o.wall_s = rep.wall_s;
  o.finding = rep.timeout ? fmt("wall budget of %.0f s ran out at t=%.6g s of %.6g s", opt.budget_s, rep.sim_s, opt.soak_s)
                          : rep.fault;
  const std::string figures = soak_figures(rep, m);
  r = finish(r, o, "no fault: " + figures);
  if (!o.held || o.timeout) r.held += "; figures: " + figures;
  r.figures = {{"sim_s", rep.sim_s},
               {"cpu_s", rep.cpu_s},
               {"cycles", static_cast<double>(rep.cycles)},
               {"commands_applied", static_cast<double>(rep.applied)},
               {"commands_refused", static_cast<double>(rep.refused)},
               {"peak_speed_m_s", rep.peaks.max_speed},
               {"peak_speed_time_s", rep.peaks.max_speed_time},
               {"peak_speed_particle", static_cast<double>(rep.peaks.fastest)},
               {"peak_kinetic_j", rep.peaks.max_kinetic},
               {"kinetic_limit_j", rep.kinetic_limit},
               {"cycle_end_kinetic_first_j", rep.cycle_end_kinetic_first},
               {"cycle_end_kinetic_last_j", rep.cycle_end_kinetic_last},
               {"worst_volume_drift", rep.peaks.max_volume_drift},
               {"max_displacement_mm", rep.peaks.max_displacement * 1e3},
               {"min_margin_mm", (rep.peaks.min_margin < 1e299 ? rep.peaks.min_margin : 0.0) * 1e3},
               {"cycle_drift_max_mm", rep.cycle_drift_max * 1e3},
               {"cycle_drift_particle", static_cast<double>(rep.cycle_drift_particle)},
               {"cycle_drift_rms_mm", rep.cycle_drift_rms * 1e3}};
  for (const auto& [name, d] : rep.end_volume_drift) r.figures.emplace_back("end_volume_drift_" + name, d);
  return r;
}

// The stress cases of each instrument kind (engine/tools/tool_kind.h), in run order; a new kind
// adds its cases here. A case runs when the scenario holds its kind's section (it reports
// "skipped" otherwise).
struct KindStressCase {
  const ToolKind* kind;
  const char* name;
  StressResult (*run)(const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0,
                      const std::string& name);
};

const std::vector<KindStressCase>& kind_stress_cases() {
  static const std::vector<KindStressCase> cases = {
      {&NeedleTool::kind(), "needle_1m_s", needle_case},
      {&NeedleTool::kind(), "gun_fired", needle_case},
      {&NeedleTool::kind(), "pullback_stuck", needle_case},
      {&ProbeTool::kind(), "probe_push_rotate",
       [](const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0, const std::string&) {
         return probe_case(spec, opt, m0);
       }},
      {&FillingTool::kind(), "fill_max_rate",
       [](const ScenarioSpec& spec, const StressOptions& opt, const std::shared_ptr<const Model>& m0, const std::string&) {
         return fill_case(spec, opt, m0);
       }},
  };
  return cases;
}

const KindStressCase* find_kind_stress_case(const std::string& name) {
  for (const KindStressCase& c : kind_stress_cases())
    if (name == c.name) return &c;
  return nullptr;
}

}  // namespace

std::string soak_script_for(const ScenarioSpec& spec, const StressOptions& opt) {
  namespace fs = std::filesystem;
  if (opt.soak_script == "none") return "";
  if (!opt.soak_script.empty()) return opt.soak_script;
  if (spec.file.empty()) return "";
  const fs::path f = fs::path(spec.file).parent_path() / "scripts" / fs::path(spec.file).filename();
  if (!fs::exists(f)) return "";
  // only a script written for this scene (its `scenario:` key): another scene's would be refused
  try {
    const Script s = parse_script_file(f.string());
    return s.scenario.empty() || s.scenario == spec.name ? f.string() : "";
  } catch (const InputError&) {
    return f.string();  // bad: let the soak case report it
  }
}

std::vector<std::string> all_stress_case_names() {
  std::vector<std::string> n = {"stable_substep", "stiff_inclusion_10", "stiff_inclusion_100", "stiff_inclusion_1000"};
  for (const KindStressCase& c : kind_stress_cases()) n.push_back(c.name);
  n.insert(n.end(), {"random_impulses", "random_commands", "soak"});
  return n;
}

std::vector<std::string> stress_case_names(const ScenarioSpec& spec, const StressOptions& opt) {
  std::vector<std::string> n = {"stable_substep"};
  for (double ratio : opt.quick ? std::vector<double>{1000} : std::vector<double>{10, 100, 1000})
    n.push_back(fmt("stiff_inclusion_%g", ratio));
  for (const KindStressCase& c : kind_stress_cases()) n.push_back(c.name);
  n.insert(n.end(), {"random_impulses", "random_commands", "soak"});
  if (!opt.cases.empty())
    std::erase_if(n, [&](const std::string& c) { return std::find(opt.cases.begin(), opt.cases.end(), c) == opt.cases.end(); });
  return n;
}

std::vector<StressResult> run_stress_cases(const ScenarioSpec& spec, std::shared_ptr<const Model> m0,
                                           const StressOptions& opt,
                                           const std::function<void(const std::string&)>& on_case) {
  std::vector<StressResult> out;
  for (const std::string& name : stress_case_names(spec, opt)) {
    if (on_case) on_case(spec.name + ": " + name);
    const auto t0 = Clock::now();
    StressResult r{spec.name, name};
    try {
      if (!m0) m0 = compile_scenario(spec);
      if (name == "stable_substep") r = stable_substep(spec, opt, m0);
      else if (name.rfind("stiff_inclusion_", 0) == 0) r = stiff_inclusion(spec, opt, std::stod(name.substr(16)), *m0);
      else if (const KindStressCase* k = find_kind_stress_case(name)) r = k->run(spec, opt, m0, name);
      else if (name == "random_impulses") r = impulses(spec, opt, m0);
      else if (name == "random_commands") r = random_commands(spec, opt, m0);
      else r = soak(spec, opt);
    } catch (const InputError& e) {
      // A tool refusing the stressed setup up front (e.g. a needle path outside the scene) is a
      // clean refusal, not a crash.
      r.status = "refused";
      r.held = std::string("refused cleanly: ") + e.what();
    } catch (const std::exception& e) {
      r.status = "FAIL";
      r.held = name + " threw: " + e.what();
    }
    r.scene = spec.name;
    r.name = name;
    if (r.wall_s == 0) r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    out.push_back(r);
  }
  return out;
}

}  // namespace ps::app
