// Material stage of compile_scenario: each particle's mass (from its component's enclosed volume),
// k_c, k_f, damping, and what its material model gives it (material_models.h: shape-memory
// stiffness k_e from E and spacing, or given; the moduli of the strain, tet and shell models);
// then the overrides: regions with other values.
#include <string>

#include "engine/scenario/compile_stages.h"
#include "engine/scenario/material_models.h"
#include "engine/util/error.h"

namespace ps {

namespace {

void component_materials(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  const int n = m.particle_count();
  const auto& faces_of = work.faces_of;
  const auto& excluded_volume = work.excluded_volume;
  // materials: mass from the component's enclosed volume, stiffness from the material model
  m.mass.assign(n, 0.0);
  m.k_e.assign(n, 0.0);
  m.k_c.assign(n, 0.0);
  m.k_f.assign(n, 0.0);
  m.damping.assign(n, 0.0);
  work.strain.assign(n, StrainParticle{});
  work.tet.assign(n, TetParticle{});
  work.shell.assign(n, ShellParticle{});
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    const ComponentSpec& cs = spec.components[ci];
    const MaterialSpec& mat = find_material(spec, cs.material);
    const MaterialModelDesc& model = material_model(mat.model);
    const Component& comp = m.components[ci];
    ComponentMaterialInput in{spec, mat, cs, comp};
    if (model.check) model.check(in);
    double volume = 0.0;
    for (const auto& f : faces_of[ci]) volume += m.rest_pos[f[0]].dot(m.rest_pos[f[1]].cross(m.rest_pos[f[2]])) / 6.0;
    if (!cs.volumetric) {
      // membrane: mass of a wall one spacing thick, or of the shell model's own thickness
      double area = 0.0;
      for (const auto& f : faces_of[ci])
        area += 0.5 * (m.rest_pos[f[1]] - m.rest_pos[f[0]]).cross(m.rest_pos[f[2]] - m.rest_pos[f[0]]).norm();
      volume = area * (mat.model == MaterialModel::Shell ? *mat.thickness : cs.spacing);
    }
    volume -= excluded_volume[ci];  // the organs inside a fat block are not fat
    if (!(volume > 0.0))
      throw CompileError("component '" + cs.name + "': surface encloses no positive volume (inverted or open)");
    const double pm = mat.density * volume / comp.particle_count;
    in.volume = volume;
    ParticleMaterial pmat;
    model.moduli(in, pmat, work.warnings);
    if (mat.k_e) pmat.k_e = *mat.k_e;
    work.uses_model[static_cast<size_t>(mat.model)] = true;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      m.mass[p] = pm;
      m.k_e[p] = pmat.k_e;
      m.k_c[p] = mat.k_c;
      m.k_f[p] = mat.k_f;
      m.damping[p] = mat.damping;
      work.strain[p] = pmat.strain;
      work.tet[p] = pmat.tet;
      work.shell[p] = pmat.shell;
    }
  }
}

void apply_overrides(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  for (size_t oi = 0; oi < spec.overrides.size(); ++oi) {
    const OverrideSpec& o = spec.overrides[oi];
    const int ci = m.find_component(o.component);
    const Component& comp = m.components[ci];
    const MaterialModelDesc& model = material_model(find_material(spec, spec.components[ci].material).model);
    int hits = 0;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      if (!o.region.contains(m.rest_pos[p])) continue;
      ++hits;
      if (o.young) model.override_young(*o.young, comp.spacing, p, m, work);
      if (o.k_e) m.k_e[p] = *o.k_e;
      if (o.k_c) m.k_c[p] = *o.k_c;
      if (o.k_f) m.k_f[p] = *o.k_f;
      if (o.damping) m.damping[p] = *o.damping;
    }
    if (hits == 0)
      throw InputError(spec.file, o.loc.line, "overrides[" + std::to_string(oi) + "].region",
                       "selects no particle of component '" + o.component + "'");
  }
}

}  // namespace

void compile_material(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  component_materials(spec, m, work);
  apply_overrides(spec, m, work);
}

}  // namespace ps
