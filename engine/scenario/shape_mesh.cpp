#include "engine/scenario/shape_mesh.h"

#include "engine/util/error.h"

namespace ps {

ParticleSet particles_from_mesh(const ComponentSpec& c, const std::string& file) {
  // Mesh import lands with the anatomy work (engine/mesh/mesh_import.h).
  throw InputError(file, c.loc.line, "components." + c.name + ".mesh", "mesh shapes are not available in this build");
}

}  // namespace ps
