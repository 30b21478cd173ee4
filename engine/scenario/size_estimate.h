// How big a scenario will be, estimated from the spec alone (shape extents and spacings) before
// compile allocates anything: a spacing of 0.001 mm in a 200 mm box must be refused up front with
// the key to change, not discovered by running out of memory.
#pragma once
#include <string>

#include "engine/spec/scenario_spec.h"

namespace ps {

// The most substeps compile accepts per tick (the parser's limit on time.substeps too).
inline constexpr int kMaxSubstepsPerTick = 100000;

struct ScenarioLimits {
  double max_particles = 2.0e6;        // largest scene compile accepts [-]
  double max_bytes = 8.0 * (1u << 30); // estimated model + state memory [B]
};

// Peak memory per particle while compiling and running, rounded up from measurements: `prostatesim
// check config/biopsy.yaml` reports 5.16 MiB model + state for 4024 particles (1.3 KB each; peak
// RSS 34 MB including meshes and compile temporaries, ~5 KB per particle above the 13 MB
// baseline); a 120 mm paper-model cube went from 41 MB (29 791 particles) to 230 MB
// (226 981), 0.96 KB per particle. 4 KB covers the richer neighbourhoods of the anatomy.
inline constexpr double kBytesPerParticle = 4096.0;

struct SizeEstimate {
  double particles = 0.0;  // upper estimate [-]
  double bytes = 0.0;      // particles * kBytesPerParticle [B]
};

// Upper estimate of one component's particles: lattice points of its shape's bounding volume
// at its spacing plus a surface layer. Mesh shapes read only the file's bounding box.
SizeEstimate estimate_component_size(const ComponentSpec& component, const std::string& scenario_file);

// Throws InputError (file:line of the component, key components[i].spacing_mm) when the scene
// would exceed `limits`, naming the limit, the estimate and the spacing that would fit.
SizeEstimate check_scenario_size(const ScenarioSpec& spec, const ScenarioLimits& limits = {});

}  // namespace ps
