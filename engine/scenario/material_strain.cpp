// model: strain, the shape-memory term with a small k_e plus the strain-memory term of one
// cluster per particle (docs/model.md "Strain memory"; engine/model/strain_clusters.h).
#include <string>

#include "engine/model/strain_clusters.h"
#include "engine/scenario/material_models.h"
#include "engine/scenario/model_hash.h"
#include "engine/util/error.h"

namespace ps {

namespace {

void strain_check(const ComponentMaterialInput& in) {
  if (!in.cs.volumetric)
    throw InputError(in.spec.file, in.mat.loc.line, "materials." + in.mat.name + ".model",
                     "model: strain needs volumetric components, '" + in.cs.name + "' is fill: surface");
}

void strain_moduli_of(const ComponentMaterialInput& in, ParticleMaterial& out, std::vector<std::string>&) {
  const MaterialSpec& mat = in.mat;
  StrainParticle& sp = out.strain;
  const double nu = local_poisson(mat);
  if (mat.k_s) {  // raw: mu = k_s / h, lambda from the same local Poisson ratio
    sp.mu = *mat.k_s / in.cs.spacing;
    sp.lambda = 2.0 * sp.mu * nu / (1.0 - 2.0 * nu);
  } else {
    const StrainModuli sm = strain_moduli(*mat.young, nu);
    sp.mu = sm.mu;
    sp.lambda = sm.lambda;
  }
  sp.volume = in.volume / in.comp.particle_count;
  out.k_e = strain_shape_memory_stiffness(sp.mu, in.cs.spacing);
}

// the same local Poisson ratio, the new modulus
void strain_override_young(double young_pa, double spacing_m, int p, Model& m, CompileWork& work) {
  StrainParticle& sp = work.strain[p];
  const double nu = sp.lambda / (2.0 * (sp.lambda + sp.mu));
  const StrainModuli sm = strain_moduli(young_pa, nu);
  sp.mu = sm.mu;
  sp.lambda = sm.lambda;
  m.k_e[p] = strain_shape_memory_stiffness(sm.mu, spacing_m);
}

// after the surfaces: the clusters' consistency condition uses them
void strain_build(const ScenarioSpec&, Model& m, CompileWork& work) {
  for (auto& w : build_strain_clusters(m, work.strain)) work.warnings.push_back(w);
}

bool strain_present(const Model& m) { return m.strain.count() > 0; }

void strain_add_forces(const Model& m, State& s, TetPass pass) {
  if (pass != TetPass::SlowOnly && m.strain.count() > 0) add_strain_memory_forces(m, s, 50);  // R converged at each probe
}

// (2 mu V + lambda V) |g|^2 + k_r per cluster member
void strain_add_stiffness(const Model& m, bool, ProxyForm, std::vector<double>& d) {
  const StrainClusters& sc = m.strain;
  for (int c = 0; c < sc.count(); ++c)
    for (int i = sc.start[c]; i < sc.start[c + 1]; ++i)
      d[sc.member[i]] += (sc.mu2v[c] + sc.k_v[c]) * sc.g[i].squaredNorm() + sc.k_r[c];
}

// the clusters, their rest offsets, fit and gradient weights and moduli
void strain_hash(const Model& m, ModelHasher& h) {
  const StrainClusters& c = m.strain;
  h.vec(c.centre);
  h.vec(c.start);
  h.vec(c.member);
  for (const std::vector<Vec3>* v : {&c.d0, &c.q, &c.g})
    for (const Vec3& x : *v)
      for (int k = 0; k < 3; ++k) h.pod(x[k]);
  h.vec(c.mu2v);
  h.vec(c.k_v);
  h.vec(c.k_r);
}

}  // namespace

const MaterialModelDesc kStrainMaterial{MaterialModel::Strain, "strain", Stage::StrainMemory, strain_check, strain_moduli_of,
                                        strain_override_young, strain_build, strain_present, strain_add_forces,
                                        strain_add_stiffness, strain_memory_energy, strain_hash};

}  // namespace ps
