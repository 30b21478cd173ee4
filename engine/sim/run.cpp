#include "engine/sim/run.h"

#include <chrono>
#include <cmath>

#include "engine/step/stages.h"

namespace ps {

std::map<std::string, double> volume_errors(const Model& m, const State& s) {
  std::map<std::string, double> out;
  for (size_t i = 0; i < m.surfaces.size(); ++i) {
    const Surface& surf = m.surfaces[i];
    if (m.components[surf.component].kind == ComponentKind::Rigid) continue;
    const double v = surface_volume(surf, s.x);
    out[m.components[surf.component].name] = std::abs(v - s.target_volume[i]) / std::abs(s.target_volume[i]);
  }
  return out;
}

RunResult run_simulation(Simulation& sim, const RunOptions& opt) {
  RunResult r;
  const Model& m = sim.model();
  r.warnings = m.compile_warnings;
  const auto t0 = std::chrono::steady_clock::now();
  const int64_t ticks = static_cast<int64_t>(std::llround(opt.duration / m.dt));
  double calm = 0.0;
  for (int64_t k = 0; k < ticks; ++k) {
    if (!sim.tick()) {
      r.faulted = true;
      r.fault = sim.state().fault.describe(m);
      r.warnings.push_back(r.fault);
      break;
    }
    if (opt.until_rest) {
      const double ke = kinetic_energy(m, sim.state());
      calm = ke < opt.rest_energy ? calm + m.dt : 0.0;
      if (calm >= opt.rest_hold) { r.at_rest = true; break; }
    }
  }
  r.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const State& s = sim.state();
  r.steps = s.step;
  r.sim_time = s.time;
  if (!r.faulted) {
    r.kinetic_energy = kinetic_energy(m, s);
    r.max_speed = max_speed(s);
    r.volume_error = volume_errors(m, s);
  }
  if (opt.until_rest && !r.at_rest && !r.faulted)
    r.warnings.push_back("did not come to rest within " + std::to_string(opt.duration) + " s");
  if (s.clamp_count > 0) r.warnings.push_back("safety clamps acted " + std::to_string(s.clamp_count) + " times");
  return r;
}

}  // namespace ps
