// Compiled scenes are cached per process (compiling the 10k cube takes a while); each benchmark
// run builds its own Simulation from the cached Model and warms it up so the state is deformed.
#pragma once
#include <map>
#include <memory>
#include <string>

#include "bench/scenes.h"
#include "engine/step/simulation.h"

namespace ps::bench {

inline std::shared_ptr<const Model> cached_scene(const std::string& name) {
  static std::map<std::string, std::shared_ptr<const Model>> cache;
  auto& m = cache[name];
  if (!m) m = scene_by_name(name);
  return m;
}

// Substep the compiler chose for the scene (model.dt / model.substeps) [s].
inline double substep(const Model& m) { return m.dt / m.substeps; }

// Simulation of the scene after `warm` substeps (sagging under gravity, volume solve active).
inline std::unique_ptr<Simulation> warmed(const std::string& name, int warm = 200) {
  auto sim = std::make_unique<Simulation>(cached_scene(name));
  const double h = substep(sim->model());
  for (int i = 0; i < warm; ++i) sim->step(h);
  return sim;
}

}  // namespace ps::bench
