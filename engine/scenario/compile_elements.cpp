// Elements stage of compile_scenario (after the surfaces, which all use): the strain model's
// clusters, the tet model's elements and the shell model's membranes, with what they change in
// the shape-memory term.
#include <string>
#include <vector>

#include "engine/model/discrete_coordinates.h"
#include "engine/model/shell_elements.h"
#include "engine/model/strain_clusters.h"
#include "engine/model/tet_elements.h"
#include "engine/scenario/compile_stages.h"

namespace ps {

void compile_elements(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  const int n = m.particle_count();
  const auto& strain = work.strain;
  const auto& tet = work.tet;
  const auto& shell = work.shell;
  const bool any_strain = work.any_strain, any_tet = work.any_tet, any_shell = work.any_shell;
  auto& warnings = work.warnings;
  auto& notes = work.notes;
  if (any_strain)  // after the surfaces: the clusters' consistency condition uses them
    for (auto& w : build_strain_clusters(m, strain)) warnings.push_back(w);
  if (any_tet) {  // after the surfaces: elements outside a component's surface are dropped
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
      (w.find("left out") != std::string::npos ? notes : warnings).push_back(w);
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
  if (any_shell) {  // after the surfaces: the shells are their faces
    build_shell_elements(m, shell);
    // the elements carry the wall's stiffness (k_e = 0): no attractor to evaluate
    bool dropped = false;
    for (int p = 0; p < n; ++p)
      if (m.shape_memory[p] && shell[p].mu > 0.0 && !(m.k_e[p] > 0.0)) { m.shape_memory[p] = 0; dropped = true; }
    if (dropped) compute_discrete_coordinates(m);
  }
  m.any_shape_memory = false;
  for (int p = 0; p < n; ++p) m.any_shape_memory |= (m.shape_memory[p] && m.k_e[p] > 0.0);
}

}  // namespace ps
