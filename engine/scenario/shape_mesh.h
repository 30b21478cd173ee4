// Particles of a component whose shape is a mesh file (imported, checked, remeshed to the
// component spacing, then surface-only or volumetric fill).
#pragma once
#include <string>
#include <vector>

#include "engine/scenario/particle_set.h"
#include "engine/spec/scenario_spec.h"

namespace ps {

// `warnings` (optional) receives a line when the remeshed surface is not at the spacing asked for
// (thin walls: coarsened by edge collapse, or left at the refined input).
ParticleSet particles_from_mesh(const ComponentSpec& component, const std::string& scenario_file,
                                std::vector<std::string>* warnings = nullptr);

}  // namespace ps

namespace ps {
// The imported, repaired, remeshed closed surface of a mesh-shaped component [m].
TriMesh load_component_surface(const ComponentSpec& component, const std::string& scenario_file, double spacing,
                               std::vector<std::string>* warnings = nullptr);
}  // namespace ps
