// model: paper, the shape-memory term alone (paper §3.2; engine/model/material.h maps E and the
// spacing to k_e). Its force stage, ShapeMemory, also runs the attractors the other models keep
// (the strain model's small k_e, tet particles no element reaches).
#include <string>

#include "engine/scenario/material_models.h"
#include "engine/util/error.h"

namespace ps {

namespace {

void paper_moduli(const ComponentMaterialInput& in, ParticleMaterial& out, std::vector<std::string>& warnings) {
  const ComponentSpec& cs = in.cs;
  out.k_e = in.mat.young ? shape_memory_stiffness(*in.mat.young, cs.spacing) : 0.0;
  if (!in.mat.k_e && in.comp.kind != ComponentKind::Rigid && (cs.spacing < kCalibratedSpacingMin || cs.spacing > kCalibratedSpacingMax))
    warnings.push_back("component '" + cs.name + "': spacing " + std::to_string(cs.spacing * 1e3) +
                       " mm is outside the 4-10 mm range where the E -> k_e mapping was calibrated");
}

void paper_override_young(double young_pa, double spacing_m, int p, Model& m, CompileWork&) {
  m.k_e[p] = shape_memory_stiffness(young_pa, spacing_m);
}

bool paper_present(const Model& m) { return m.any_shape_memory; }

void paper_add_forces(const Model& m, State& s, TetPass pass) {
  if (pass != TetPass::SlowOnly) add_shape_memory_forces(m, s);
}

// k_e of its own attractor plus the shares of the attractors it enters, w^2 k_e
void paper_add_stiffness(const Model& m, bool, ProxyForm, std::vector<double>& d) {
  for (int p = 0, n = m.particle_count(); p < n; ++p) {
    if (!m.shape_memory[p]) continue;
    d[p] += m.k_e[p];
    for (int a = m.nbr_start[p]; a < m.nbr_start[p + 1]; ++a) d[m.nbr[a]] += m.k_e[p] * m.nbr_w[a] * m.nbr_w[a];
  }
}

// sum 1/2 k_e |P* - P|^2 with the attractors at s.x (the default redistribution's force is its
// exact gradient: shape_memory.cpp)
double paper_energy(const Model& m, const State& s) {
  State at = s;
  add_shape_memory_forces(m, at);
  double e = 0.0;
  for (int p = 0, n = m.particle_count(); p < n; ++p)
    if (m.shape_memory[p]) e += 0.5 * m.k_e[p] * (at.attractor[p] - s.x[p]).squaredNorm();
  return e;
}

}  // namespace

const MaterialModelDesc kPaperMaterial{MaterialModel::Paper, "paper", Stage::ShapeMemory, nullptr, paper_moduli,
                                       paper_override_young, nullptr, paper_present, paper_add_forces, paper_add_stiffness,
                                       paper_energy, nullptr};

}  // namespace ps
