// Particles of a component whose shape is a mesh file (imported, checked, remeshed to the
// component spacing, then surface-only or volumetric fill).
#pragma once
#include <string>

#include "engine/scenario/particle_set.h"
#include "engine/scenario/scenario_spec.h"

namespace ps {

ParticleSet particles_from_mesh(const ComponentSpec& component, const std::string& scenario_file);

}  // namespace ps

namespace ps {
// The imported, repaired, remeshed closed surface of a mesh-shaped component [m].
TriMesh load_component_surface(const ComponentSpec& component, const std::string& scenario_file, double spacing);
}  // namespace ps
