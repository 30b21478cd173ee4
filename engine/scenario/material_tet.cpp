// model: tet, elastic elements over a Delaunay tetrahedralisation of the particles: isochoric
// neo-Hookean shear per element, nodal pressure per particle (docs/model.md "Tet model";
// engine/model/tet_elements.h, engine/step/tet_elastic.cpp).
#include <algorithm>
#include <string>
#include <utility>

#include "engine/model/discrete_coordinates.h"
#include "engine/model/tet_elements.h"
#include "engine/scenario/material_models.h"
#include "engine/scenario/model_hash.h"
#include "engine/util/error.h"

namespace ps {

namespace {

void tet_check(const ComponentMaterialInput& in) {
  if (!in.cs.volumetric)
    throw InputError(in.spec.file, in.mat.loc.line, "materials." + in.mat.name + ".model",
                     "model: tet needs volumetric components, '" + in.cs.name + "' is fill: surface");
}

// k_e = 0: the elements carry the whole stiffness
void tet_moduli(const ComponentMaterialInput& in, ParticleMaterial& out, std::vector<std::string>&) {
  const StrainModuli sm = strain_moduli(*in.mat.young, local_poisson(in.mat));
  out.tet.mu = sm.mu;
  out.tet.lambda = sm.lambda;
  out.tet.implicit_pressure = in.mat.implicit_pressure;
}

void tet_override_young(double young_pa, double, int p, Model&, CompileWork& work) {
  TetParticle& tp = work.tet[p];
  const double nu = tp.lambda / (2.0 * (tp.lambda + tp.mu));
  const StrainModuli sm = strain_moduli(young_pa, nu);
  tp.mu = sm.mu;
  tp.lambda = sm.lambda;
}

// after the surfaces: elements outside a component's surface are dropped
void tet_build(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  const int n = m.particle_count();
  const auto& tet = work.tet;
  const auto& shell = work.shell;
  std::vector<std::vector<int>> excluded(m.components.size());
  for (size_t ci = 0; ci < spec.components.size(); ++ci)
    for (const std::string& other : spec.components[ci].exclude_inside) {
      const int oc = m.find_component(other);
      if (oc >= 0 && m.components[oc].surface >= 0) excluded[ci].push_back(m.components[oc].surface);
    }
  // links between two tet components, or a tet component and a shell (the tissue around a wall
  // reaches it through elements spanning the gap, of the tet side's material)
  std::vector<TetLink> tet_links;
  for (const LinkSpec& l : spec.links) {
    const int a = m.find_component(l.a), b = m.find_component(l.b);
    if (a < 0 || b < 0) continue;
    const int pa = m.components[a].first_particle, pb = m.components[b].first_particle;
    const bool ta = tet[pa].mu > 0.0, tb = tet[pb].mu > 0.0;
    if ((ta && tb) || (ta && shell[pb].mu > 0.0) || (tb && shell[pa].mu > 0.0)) tet_links.push_back(TetLink{a, b, l.distance});
  }
  // dropping slivers and hull elements is by design (tet_elements.cpp): a note, not a warning
  for (auto& w : build_tet_elements(m, tet, excluded, tet_links))
    (w.find("left out") != std::string::npos ? work.notes : work.warnings).push_back(w);
  // a particle no element reaches keeps the lattice shape-matching stiffness mu h of the
  // paper's term, so it stays attached to its neighbours
  for (int p = 0; p < n; ++p)
    if (tet[p].mu > 0.0 && m.tets.node_slot[p] < 0 && !m.k_e[p]) m.k_e[p] = tet[p].mu * m.components[m.component_of[p]].spacing;
  // an element node with k_e = 0 carries no shape-memory force: drop its triplets so the
  // shape-memory stage does not evaluate attractors that are multiplied by zero (they cost
  // about half of a tet scene's substep). The neighbour graph stays: the needle's zone search
  // walks it.
  bool dropped = false;
  for (int p = 0; p < n; ++p)
    if (m.shape_memory[p] && m.tets.node_slot[p] >= 0 && !(m.k_e[p] > 0.0)) { m.shape_memory[p] = 0; dropped = true; }
  if (dropped) compute_discrete_coordinates(m);
}

bool tet_present(const Model& m) { return m.tets.count() > 0; }

void tet_add_forces(const Model& m, State& s, TetPass pass) {
  if (m.tets.count() > 0) add_tet_elastic_forces(m, s, pass);
}

void tet_add_stiffness(const Model& m, bool fast_only, ProxyForm form, std::vector<double>& d) {
  // tet elements (fast_only: the multi-rate fast group's elements, those that set the substep).
  // Shear: V0 mu |g_i|^2 per vertex, the diagonal of the element's deviatoric stiffness at rest.
  // Volume, ProxyForm::Diagonal: the diagonal of the nodal pressure term itself, kappa_n / V0_n
  // |dV_n/dx_p|^2 summed over the nodes n whose volume share x_p moves, with dV_n/dx_p = 1/4 sum
  // over the elements holding both n and p of V0_t g_p (at rest). The elements' gradients around a
  // node largely cancel in that sum (exactly, for an interior node's own share), so it is ~8x below
  // ProxyForm::ElementBound's V0 kappa |g_i|^2, each element's volume stiffness counted whole as
  // if it kept its own volume (fat and skin of the default anatomy: mean 8.0x, largest ratio to the
  // mass 16x). The diagonal sizes inertia; the element bound gates the multi-rate slow group.
  const TetElements& te = m.tets;
  const int nt_proxy = fast_only ? te.fast_count : te.count();
  const bool diagonal = form == ProxyForm::Diagonal;
  std::vector<std::vector<std::pair<int, Vec3>>> share_grad(diagonal ? te.nodes.size() : 0);  // [node] (p, dV_n/dx_p)
  for (int t = 0; t < nt_proxy; ++t) {
    const double* g = &te.g[9 * t];
    const Vec3 g1(g[0], g[1], g[2]), g2(g[3], g[4], g[5]), g3(g[6], g[7], g[8]), g0 = -(g1 + g2 + g3);
    const Vec3 gi[4] = {g0, g1, g2, g3};
    const int* v = &te.v[4 * t];
    if (!diagonal) {
      for (int i = 0; i < 4; ++i) d[v[i]] += te.vol0[t] * (te.mu[t] + te.node_kappa_explicit[te.node_slot[v[i]]]) * gi[i].squaredNorm();
      continue;
    }
    for (int i = 0; i < 4; ++i) d[v[i]] += te.vol0[t] * te.mu[t] * gi[i].squaredNorm();
    for (int j = 0; j < 4; ++j) {
      const int slot = te.node_slot[v[j]];
      if (te.node_kappa_explicit[slot] == 0.0) continue;  // implicit pressure: not a force
      auto& list = share_grad[slot];
      for (int i = 0; i < 4; ++i) {
        auto it = std::find_if(list.begin(), list.end(), [&](const auto& e) { return e.first == v[i]; });
        const Vec3 add = 0.25 * te.vol0[t] * gi[i];
        if (it == list.end()) list.emplace_back(v[i], add);
        else it->second += add;
      }
    }
  }
  for (size_t a = 0; a < share_grad.size(); ++a)
    for (const auto& [p, grad] : share_grad[a]) d[p] += te.node_kappa_explicit[a] * te.node_inv_vol0[a] * grad.squaredNorm();
}

// the elements' rest data and moduli, the implicit pressure's layout and the fast group
void tet_hash(const Model& m, ModelHasher& h) {
  h.vec(m.tets.v);
  h.vec(m.tets.g);
  h.vec(m.tets.vol0);
  h.vec(m.tets.mu);
  h.vec(m.tets.node_kappa);
  h.vec(m.tets.node_implicit);
  h.vec(m.tet_pressure.row_slot);
  h.pod(m.tet_pressure.h);
  h.pod(m.tet_pressure.iterations);
  h.pod(m.tets.fast_count);
}

}  // namespace

const MaterialModelDesc kTetMaterial{MaterialModel::Tet, "tet", Stage::TetElastic, tet_check, tet_moduli, tet_override_young,
                                     tet_build, tet_present, tet_add_forces, tet_add_stiffness, tet_elastic_energy, tet_hash};

}  // namespace ps
