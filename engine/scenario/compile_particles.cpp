// Particles stage of compile_scenario: every component's particles (box, cylinder or mesh shape;
// components that exclude others, the fat around the organs, filled after them), appended to the
// Model contiguously per component, with their neighbour lists and closed surfaces.
#include <algorithm>

#include "engine/scenario/compile_stages.h"
#include "engine/scenario/particle_set.h"
#include "engine/scenario/scene_regions.h"
#include "engine/scenario/shape_mesh.h"
#include "engine/util/error.h"

namespace ps {

namespace {

ParticleSet build_particles(const ComponentSpec& c, const std::string& file, std::vector<std::string>* warnings) {
  const ShapeSpec& s = c.shape;
  switch (s.kind) {
    case ShapeSpec::Box: {
      const Vec3 size = s.max - s.min;
      if (size.minCoeff() < c.spacing)
        throw InputError(file, c.loc.line, "components." + c.name + ".spacing_mm",
                         "spacing is larger than the smallest box side");
      return box_particles(s.min, s.max, c.spacing, c.volumetric);
    }
    case ShapeSpec::Cylinder: {
      if (2 * s.radius < c.spacing || s.length < c.spacing)
        throw InputError(file, c.loc.line, "components." + c.name + ".spacing_mm",
                         "spacing is larger than the cylinder diameter or length");
      const TriMesh surf = cylinder_surface(s.base, s.axis, s.radius, s.length, c.spacing);
      if (!c.volumetric) return surface_particles(surf);
      const Vec3 ax = s.axis.normalized();
      auto radial = [&](const Vec3& p) {
        const Vec3 d = p - s.base;
        return std::pair{(d - d.dot(ax) * ax).norm(), d.dot(ax)};
      };
      return volumetric_particles(
          surf, c.spacing,
          [&](const Vec3& p) {
            auto [r, z] = radial(p);
            return r < s.radius && z > 0 && z < s.length;
          },
          [&](const Vec3& p) {
            auto [r, z] = radial(p);
            return std::min({s.radius - r, z, s.length - z});
          });
    }
    case ShapeSpec::Mesh: return particles_from_mesh(c, file, warnings);
  }
  return {};
}

}  // namespace

void compile_particles(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  work.faces_of.assign(spec.components.size(), {});
  work.excluded_volume.assign(spec.components.size(), 0.0);
  auto& nbrs = work.nbrs;
  auto& faces_of = work.faces_of;
  auto& excluded_volume = work.excluded_volume;
  auto& warnings = work.warnings;
  // particles of every component, contiguous per component
  // components that exclude others (fat around organs) are filled after the others
  std::vector<ParticleSet> sets(spec.components.size());
  for (size_t ci = 0; ci < spec.components.size(); ++ci)
    if (spec.components[ci].exclude_inside.empty()) sets[ci] = build_particles(spec.components[ci], spec.file, &warnings);
  for (size_t ci = 0; ci < spec.components.size(); ++ci)
    if (!spec.components[ci].exclude_inside.empty())
      sets[ci] = anatomy::fill_excluding(spec, ci, sets, &excluded_volume[ci]);
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    const ComponentSpec& cs = spec.components[ci];
    ParticleSet set = std::move(sets[ci]);
    if (set.pos.empty())
      throw InputError(spec.file, cs.loc.line, "components." + cs.name, "component has no particles");
    Component comp;
    comp.name = cs.name;
    comp.kind = cs.kind == "rigid" ? ComponentKind::Rigid : cs.kind == "active" ? ComponentKind::Active : ComponentKind::Elastic;
    comp.role = resolve_role(cs.role, cs.name, comp.kind == ComponentKind::Rigid);
    comp.first_particle = m.particle_count();
    comp.particle_count = static_cast<int>(set.pos.size());
    comp.spacing = cs.spacing;
    comp.volumetric = cs.volumetric;
    comp.fibre_dir = cs.fibre;
    comp.active_force = cs.active_stress * cs.spacing * cs.spacing;
    const int off = comp.first_particle;
    for (size_t p = 0; p < set.pos.size(); ++p) {
      m.rest_pos.push_back(set.pos[p]);
      m.component_of.push_back(static_cast<int>(ci));
      m.on_surface.push_back(set.on_surface[p]);
      std::vector<int> nb;
      for (int q : set.nbrs[p]) nb.push_back(q + off);
      nbrs.push_back(std::move(nb));
    }
    for (auto f : set.faces) faces_of[ci].push_back({f[0] + off, f[1] + off, f[2] + off});
    m.components.push_back(comp);
  }
}

}  // namespace ps
