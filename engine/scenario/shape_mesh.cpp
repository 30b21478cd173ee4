#include "engine/scenario/shape_mesh.h"

#include <stdexcept>

#include "engine/mesh/mesh_check.h"
#include "engine/mesh/mesh_import.h"
#include "engine/mesh/mesh_query.h"
#include "engine/mesh/mesh_simplify.h"
#include "engine/util/error.h"

namespace ps {

TriMesh load_component_surface(const ComponentSpec& c, const std::string& file, double spacing) {
  const MeshShapeSpec& ms = c.shape.mesh;
  MeshImportOptions opt;
  // the importer converts units itself (and checks the size in metres after that conversion)
  opt.units = ms.unit_scale == 1e-3 ? "mm" : ms.unit_scale == 1e-2 ? "cm" : ms.unit_scale == 1e-1 ? "dm" : "m";
  opt.scale = ms.scale;
  opt.rotate_deg = ms.rotate_deg;
  opt.translate_m = ms.translate;
  TriMesh closed = repair_closed_surface(import_mesh(ms.file, opt), ms.file);
  try {
    return remesh_to_spacing(closed, spacing);
  } catch (const std::invalid_argument& e) {
    throw InputError(ms.file, 0, "components." + c.name + ".mesh", std::string("cannot remesh: ") + e.what());
  }
}

ParticleSet particles_from_mesh(const ComponentSpec& c, const std::string& file) {
  const TriMesh surf = load_component_surface(c, file, c.spacing);
  if (!c.volumetric) return surface_particles(surf);
  const MeshQuery q(surf);
  return volumetric_particles(
      surf, c.spacing, [&](const Vec3& p) { return q.inside(p); }, [&](const Vec3& p) { return q.distance(p); });
}

}  // namespace ps
