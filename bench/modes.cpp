// Untimed modes of prostatesim_bench (see main.cpp) and the stage-by-stage step.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_modes.h"
#include "bench/scenes.h"
#include "engine/step/stages.h"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define PS_CALLGRIND_TOGGLE() CALLGRIND_TOGGLE_COLLECT
#else
#define PS_CALLGRIND_TOGGLE() ((void)0)
#endif

namespace ps::bench {

namespace {
const char* const kScenes[] = {"cube11", "cube11i", "cube22", "cube22i", "cyl", "cyli", "biopsy"};

int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

bool timed_step(Simulation& sim, double dt, StageTimes& times) {
  const Model& m = sim.model();
  State& s = sim.state();
  if (s.fault.kind != StepFault::None) return false;
  const double t_end = s.time + dt;
  int64_t t0 = now_ns();
  for (Stage st : sim.pipeline()) {
    bool ok = true;
    switch (st) {
      case Stage::ImposedDisplacement: apply_imposed_displacements(m, s, s.time); break;
      case Stage::ExternalForces: clear_and_add_external_forces(m, s, s.time); break;
      case Stage::ShapeMemory: add_shape_memory_forces(m, s); break;
      case Stage::StrainMemory: add_strain_memory_forces(m, s); break;
      case Stage::TetElastic: add_tet_elastic_forces(m, s); break;  // every element (no tick here)
      case Stage::ShellElastic: add_shell_elastic_forces(m, s); break;
      case Stage::TetTickEnd: break;  // the All pass above already applied the slow elements
      case Stage::ActiveFibres: add_active_forces(m, s); break;
      case Stage::RigidForces: gather_rigid_forces(m, s); break;
      case Stage::Integrate: integrate(m, s, dt); break;
      case Stage::RigidIntegrate: integrate_rigid_bodies(m, s, dt); break;
      case Stage::TetPressure: project_tet_pressure(m, s, dt); break;
      case Stage::LocalConstraints: apply_local_constraints(m, s, t_end); break;
      case Stage::Volume: ok = project_volumes(m, s); break;
      case Stage::AdjustVelocity: adjust_velocities(s, dt); break;
      case Stage::Check:
        s.time = t_end;
        ++s.step;
        ok = check_state(m, s);
        break;
      default: return false;  // tool stages: timed_step is for scenes without tools
    }
    const int64_t t1 = now_ns();
    times.ns[static_cast<int>(st)] += t1 - t0;
    t0 = t1;
    if (!ok) return false;
  }
  return true;
}

int print_info() {
  std::printf("%-8s %9s %9s %9s %12s %9s %9s %12s %9s\n", "scene", "particles", "surface", "nbrs/p", "beta/p",
              "faces", "substeps", "substep_s", "est_dt_s");
  for (const char* name : kScenes) {
    auto m = scene_by_name(name);
    int surf = 0;
    for (uint8_t o : m->on_surface) surf += o;
    const int n = m->particle_count();
    int faces = 0;
    for (const Surface& s : m->surfaces) faces += static_cast<int>(s.faces.size());
    std::printf("%-8s %9d %9d %9.2f %12.2f %9d %9d %12.4g %9.4g\n", name, n, surf,
                static_cast<double>(m->nbr.size()) / n, static_cast<double>(m->beta.size()) / n, faces, m->substeps,
                m->dt / m->substeps, m->stable_dt_estimate);
  }
  return 0;
}

int run_steps(const std::string& scene, int steps) {
  auto m = scene_by_name(scene);
  if (!m) { std::fprintf(stderr, "unknown scene '%s'\n", scene.c_str()); return 2; }
  Simulation sim(m);
  const double h = m->dt / m->substeps;
  for (int i = 0; i < 20; ++i) sim.step(h);
  // under valgrind --tool=callgrind --collect-atstart=no only these steps are counted
  PS_CALLGRIND_TOGGLE();
  bool ok = true;
  for (int i = 0; i < steps && ok; ++i) ok = sim.step(h);
  PS_CALLGRIND_TOGGLE();
  if (!ok) { std::fprintf(stderr, "%s\n", sim.state().fault.describe(*m).c_str()); return 1; }
  std::printf("%s: %d substeps of %.4g s, hash %016llx\n", scene.c_str(), steps, h,
              static_cast<unsigned long long>(hash_state(sim.state())));
  return 0;
}

int verify_shape_memory() {
  // 1. the optimised stage against the pre-optimisation reference: equal up to round-off;
  // 2. the build add_shape_memory_forces() picks on this CPU against the baseline build:
  //    bit-identical, so a replay gives the same state on any x86-64 machine.
  int bad = 0;
  std::vector<std::pair<std::string, std::shared_ptr<const Model>>> scenes;
  for (const char* name : kScenes) scenes.emplace_back(name, scene_by_name(name));
  {  // the paper's literal redistribution (no gradient pass)
    ScenarioSpec spec = parse_scenario_text(scene_text("cyl"), "verify.yaml");
    spec.linear_redistribution = true;
    scenes.emplace_back("cyl-lin", compile_scenario(spec));
  }
  for (const auto& [name, m] : scenes) {
    Simulation sim(m);
    const double h = m->dt / m->substeps;
    for (int i = 0; i < 300; ++i) sim.step(h);
    // a settled state and a randomly perturbed one (large rotations of the triplet normals)
    for (int variant = 0; variant < 2; ++variant) {
      State a = sim.state();
      if (variant == 1) {
        std::mt19937 rng(7);
        std::normal_distribution<double> N(0.0, 0.002);
        for (Vec3& x : a.x) x += Vec3(N(rng), N(rng), N(rng));
      }
      for (Vec3& f : a.f) f.setZero();
      State b = a, c = a;
      add_shape_memory_forces(*m, a);
      reference_add_shape_memory_forces(*m, b);
      detail::add_shape_memory_forces_baseline(*m, c);
      double df = 0, fmax = 0, dp = 0, pmax = 0;
      bool builds_identical = true;
      for (int p = 0; p < m->particle_count(); ++p) {
        df = std::max(df, (a.f[p] - b.f[p]).cwiseAbs().maxCoeff());
        fmax = std::max(fmax, b.f[p].cwiseAbs().maxCoeff());
        dp = std::max(dp, (a.attractor[p] - b.attractor[p]).cwiseAbs().maxCoeff());
        pmax = std::max(pmax, b.attractor[p].cwiseAbs().maxCoeff());
        builds_identical &= std::memcmp(a.f[p].data(), c.f[p].data(), sizeof(Vec3)) == 0 &&
                            std::memcmp(a.attractor[p].data(), c.attractor[p].data(), sizeof(Vec3)) == 0;
      }
      // force scale: k_e h, the shape-memory force of a 100% strain (the summed force of a settled
      // state is much smaller than its terms, so max|f| would be no yardstick for round-off)
      // (over the particles that carry shape memory: a rigid component's k_e is never used)
      double fscale = 0;
      for (int p = 0; p < m->particle_count(); ++p)
        if (m->shape_memory[p]) fscale = std::max(fscale, m->k_e[p] * m->components[m->component_of[p]].spacing);
      const bool ok = df <= 1e-13 * fscale && dp <= 1e-14 * pmax && builds_identical;
      bad += !ok;
      std::printf("%-8s %-9s vs reference: max|df| = %.3g N (%.2g of k_e h), max|dP*| = %.3g m; "
                  "AVX and baseline builds bit-identical: %s: %s\n",
                  name.c_str(), variant ? "perturbed" : "settled", df, df / fscale, dp, builds_identical ? "yes" : "NO",
                  ok ? "ok" : "MISMATCH");
    }
  }
  return bad ? 1 : 0;
}

}  // namespace ps::bench
