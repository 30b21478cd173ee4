// `prostatesim_bench --soak [N]`: issue 2's "no NaN over 100k steps of the default scene".
// config/biopsy.yaml, unchanged, with the instruments `prostatesim simulate` adds (the held
// biopsy needle and the TRUS probe), N substeps (default 100000 = 5.6 s simulated) of the
// compiler's substep. Every 1000 substeps and at the end: no fault (the step's own check
// rejects any NaN/Inf, too fast or too far particle), every position and velocity finite, and
// the relative volume error of every volume-constrained surface <= 1e-9. Prints the wall and CPU
// time; exits 0 when all held, 1 otherwise. A hand-run command, not a unit test: at ~1.1 ms per
// substep it runs ~2 minutes on one core (docs/performance.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "bench/bench_modes.h"
#include "bench/scenes.h"
#include "engine/sim/run.h"
#include "engine/sim/scene.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"

namespace ps::bench {

namespace {
double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// worst relative volume error of the volume-constrained surfaces; false if a state is not finite
bool state_ok(const Model& m, const State& s, double& worst_volume) {
  for (size_t p = 0; p < s.x.size(); ++p)
    if (!s.x[p].allFinite() || !s.v[p].allFinite()) return false;
  const auto err = volume_errors(m, s);
  for (const Surface& surf : m.surfaces)
    if (surf.volume_constrained) worst_volume = std::max(worst_volume, err.at(m.components[surf.component].name));
  return true;
}
}  // namespace

int soak(int substeps) {
  const std::string file = std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml";
  Scene scene = load_scene(file);
  const std::shared_ptr<const Model> model = scene.model;
  Simulation& sim = *scene.sim;
  const double h = model->dt / model->substeps;
  std::printf("soak: %s, %d particles, %d substeps of %.4g s (%.3f s simulated), %zu tools\n", file.c_str(),
              model->particle_count(), substeps, h, substeps * h, sim.tools().size());
  const auto w0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  double worst_volume = 0.0;
  bool ok = true;
  int done = 0;
  while (done < substeps && ok) {
    const int chunk = std::min(1000, substeps - done);
    for (int i = 0; i < chunk && ok; ++i) ok = sim.step(h);
    done += chunk;
    if (ok) ok = state_ok(*model, sim.state(), worst_volume);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  const double cpu = cpu_seconds() - c0;
  const State& s = sim.state();
  const bool volumes = worst_volume <= 1e-9;
  std::printf("soak: %lld substeps, t = %.4f s, fault: %s, finite: %s, worst volume error %.3g (limit 1e-9), "
              "kinetic energy %.3g J, max speed %.3g m/s\n",
              static_cast<long long>(s.step), s.time,
              s.fault.kind == StepFault::None ? "none" : s.fault.describe(*model).c_str(), ok ? "yes" : "NO",
              worst_volume, kinetic_energy(*model, s), max_speed(s));
  std::printf("soak: %.1f s wall, %.1f s CPU, %.1f us CPU per substep: %s\n", wall, cpu, 1e6 * cpu / done,
              ok && volumes ? "ok" : "FAILED");
  return ok && volumes ? 0 : 1;
}

}  // namespace ps::bench
