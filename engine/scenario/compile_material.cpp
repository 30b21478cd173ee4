// Material stage of compile_scenario: each particle's mass (from its component's enclosed volume),
// shape-memory stiffness k_e (from E and spacing, or given), k_c, k_f, damping, and the per-particle
// moduli of the strain and tet models; then the overrides: regions with other values.
#include <string>

#include "engine/model/material.h"
#include "engine/scenario/compile_stages.h"
#include "engine/util/error.h"

namespace ps {

namespace {

// the local Poisson ratio of the strain, tet and shell models: the file's, or the default of an
// incompressible or a compressible material
double local_poisson(const MaterialSpec& mat) {
  return mat.poisson ? *mat.poisson : mat.incompressible ? kStrainPoissonIncompressible : kStrainPoissonDefault;
}

void component_materials(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  const int n = m.particle_count();
  const auto& faces_of = work.faces_of;
  const auto& excluded_volume = work.excluded_volume;
  auto& warnings = work.warnings;
  // materials: mass from the component's enclosed volume, stiffness from E and spacing
  m.mass.assign(n, 0.0);
  m.k_e.assign(n, 0.0);
  m.k_c.assign(n, 0.0);
  m.k_f.assign(n, 0.0);
  m.damping.assign(n, 0.0);
  work.strain.assign(n, StrainParticle{});
  work.tet.assign(n, TetParticle{});
  auto& strain = work.strain;
  auto& any_strain = work.any_strain;
  auto& tet = work.tet;
  auto& any_tet = work.any_tet;
  work.shell.assign(n, ShellParticle{});
  auto& shell = work.shell;
  auto& any_shell = work.any_shell;
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    const ComponentSpec& cs = spec.components[ci];
    const MaterialSpec& mat = find_material(spec, cs.material);
    const Component& comp = m.components[ci];
    double volume = 0.0;
    for (const auto& f : faces_of[ci]) volume += m.rest_pos[f[0]].dot(m.rest_pos[f[1]].cross(m.rest_pos[f[2]])) / 6.0;
    if (mat.shell_model && cs.volumetric)
      throw InputError(spec.file, mat.loc.line, "materials." + mat.name + ".model",
                       "model: shell is for membranes, '" + cs.name + "' is volumetric (give it fill: surface)");
    if (!cs.volumetric) {
      // membrane: mass of a wall one spacing thick (paper model) or of the shell's own thickness
      double area = 0.0;
      for (const auto& f : faces_of[ci])
        area += 0.5 * (m.rest_pos[f[1]] - m.rest_pos[f[0]]).cross(m.rest_pos[f[2]] - m.rest_pos[f[0]]).norm();
      volume = area * (mat.shell_model ? *mat.thickness : cs.spacing);
    }
    volume -= excluded_volume[ci];  // the organs inside a fat block are not fat
    if (!(volume > 0.0))
      throw CompileError("component '" + cs.name + "': surface encloses no positive volume (inverted or open)");
    const double pm = mat.density * volume / comp.particle_count;
    StrainParticle sp;
    TetParticle tp;
    ShellParticle shp;
    if (mat.shell_model) {
      const double nu = local_poisson(mat);
      shp.mu = strain_moduli(*mat.young, nu).mu;
      shp.poisson = nu;
      shp.thickness = *mat.thickness;
      any_shell = true;
    }
    if (mat.tet_model) {
      if (!cs.volumetric)
        throw InputError(spec.file, mat.loc.line, "materials." + mat.name + ".model",
                         "model: tet needs volumetric components, '" + cs.name + "' is fill: surface");
      const double nu = local_poisson(mat);
      const StrainModuli sm = strain_moduli(*mat.young, nu);
      tp.mu = sm.mu;
      tp.lambda = sm.lambda;
      tp.implicit_pressure = mat.implicit_pressure;
      any_tet = true;
    }
    if (mat.strain_model) {
      if (!cs.volumetric)
        throw InputError(spec.file, mat.loc.line, "materials." + mat.name + ".model",
                         "model: strain needs volumetric components, '" + cs.name + "' is fill: surface");
      const double nu = local_poisson(mat);
      if (mat.k_s) {  // raw: mu = k_s / h, lambda from the same local Poisson ratio
        sp.mu = *mat.k_s / cs.spacing;
        sp.lambda = 2.0 * sp.mu * nu / (1.0 - 2.0 * nu);
      } else {
        const StrainModuli sm = strain_moduli(*mat.young, nu);
        sp.mu = sm.mu;
        sp.lambda = sm.lambda;
      }
      sp.volume = volume / comp.particle_count;
      any_strain = true;
    }
    const double ke = mat.k_e               ? *mat.k_e
                      : mat.tet_model || mat.shell_model ? 0.0  // the elements carry the whole stiffness
                      : mat.strain_model    ? strain_shape_memory_stiffness(sp.mu, cs.spacing)
                                            : shape_memory_stiffness(*mat.young, cs.spacing);
    if (!mat.k_e && !mat.strain_model && !mat.tet_model && !mat.shell_model && comp.kind != ComponentKind::Rigid && (cs.spacing < kCalibratedSpacingMin || cs.spacing > kCalibratedSpacingMax))
      warnings.push_back("component '" + cs.name + "': spacing " + std::to_string(cs.spacing * 1e3) +
                         " mm is outside the 4-10 mm range where the E -> k_e mapping was calibrated");
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      m.mass[p] = pm;
      m.k_e[p] = ke;
      m.k_c[p] = mat.k_c;
      m.k_f[p] = mat.k_f;
      m.damping[p] = mat.damping;
      strain[p] = sp;
      tet[p] = tp;
      shell[p] = shp;
    }
  }
}

void apply_overrides(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  auto& strain = work.strain;
  auto& tet = work.tet;
  auto& shell = work.shell;
  for (size_t oi = 0; oi < spec.overrides.size(); ++oi) {
    const OverrideSpec& o = spec.overrides[oi];
    const int ci = m.find_component(o.component);
    const Component& comp = m.components[ci];
    int hits = 0;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      if (!o.region.contains(m.rest_pos[p])) continue;
      ++hits;
      if (o.young && shell[p].mu > 0.0) {
        shell[p].mu = strain_moduli(*o.young, shell[p].poisson).mu;
      } else if (o.young && tet[p].mu > 0.0) {
        const double nu = tet[p].lambda / (2.0 * (tet[p].lambda + tet[p].mu));
        const StrainModuli sm = strain_moduli(*o.young, nu);
        tet[p].mu = sm.mu;
        tet[p].lambda = sm.lambda;
      } else if (o.young && strain[p].mu > 0.0) {
        // strain model: the same local Poisson ratio, the new modulus
        const double nu = strain[p].lambda / (2.0 * (strain[p].lambda + strain[p].mu));
        const StrainModuli sm = strain_moduli(*o.young, nu);
        strain[p].mu = sm.mu;
        strain[p].lambda = sm.lambda;
        m.k_e[p] = strain_shape_memory_stiffness(sm.mu, comp.spacing);
      } else if (o.young) {
        m.k_e[p] = shape_memory_stiffness(*o.young, comp.spacing);
      }
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
