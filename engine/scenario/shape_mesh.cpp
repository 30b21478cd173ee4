#include "engine/scenario/shape_mesh.h"

#include <stdexcept>

#include "engine/mesh/mesh_check.h"
#include "engine/mesh/mesh_import.h"
#include "engine/mesh/mesh_query.h"
#include "engine/mesh/mesh_simplify.h"
#include "engine/util/error.h"

namespace ps {

TriMesh load_component_surface(const ComponentSpec& c, const std::string& file, double spacing,
                               std::vector<std::string>* warnings) {
  const MeshShapeSpec& ms = c.shape.mesh;
  MeshImportOptions opt;
  // the importer converts units itself (and checks the size in metres after that conversion)
  opt.units = ms.unit_scale == 1e-3 ? "mm" : ms.unit_scale == 1e-2 ? "cm" : ms.unit_scale == 1e-1 ? "dm" : "m";
  opt.scale = ms.scale;
  opt.rotate_deg = ms.rotate_deg;
  opt.translate_m = ms.translate;
  TriMesh closed = repair_closed_surface(import_mesh(ms.file, opt), ms.file);
  try {
    RemeshStats st;
    TriMesh out = remesh_to_spacing(closed, spacing, &st);
    // a surface far from the asked spacing changes the particle count and the calibration's h
    const bool off = st.mean_edge_m < 0.75 * spacing || st.mean_edge_m > 1.25 * spacing;
    if (warnings && (st.collapsed || st.fell_back || off))
      warnings->push_back("component '" + c.name + "': " + ms.file + " remeshed to a mean edge of " +
                          std::to_string(st.mean_edge_m * 1e3) + " mm for a spacing of " + std::to_string(spacing * 1e3) +
                          " mm" + (st.fell_back ? " (no valid coarsening: refined input kept)"
                                   : st.collapsed ? " (walls thinner than the spacing: coarsened by edge collapse)" : ""));
    return out;
  } catch (const std::invalid_argument& e) {
    throw InputError(ms.file, 0, "components." + c.name + ".mesh", std::string("cannot remesh: ") + e.what());
  }
}

ParticleSet particles_from_mesh(const ComponentSpec& c, const std::string& file, std::vector<std::string>* warnings) {
  const TriMesh surf = load_component_surface(c, file, c.spacing, warnings);
  if (!c.volumetric) return surface_particles(surf);
  const MeshQuery q(surf);
  return volumetric_particles(
      surf, c.spacing, [&](const Vec3& p) { return q.inside(p); }, [&](const Vec3& p) { return q.distance(p); });
}

}  // namespace ps
