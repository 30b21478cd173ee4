// Neighbours stage of compile_scenario: links across components (paper §3.1, Fig. 3: an elastic
// border particle attached to a rigid body, or given its nearest particles of the other elastic
// component as neighbours), then every neighbour list into the Model's CSR arrays.
#include <algorithm>
#include <string>
#include <utility>

#include "engine/model/discrete_coordinates.h"
#include "engine/scenario/compile_stages.h"
#include "engine/util/error.h"
#include "engine/util/spatial_grid.h"

namespace ps {

void compile_neighbours(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  const int n = m.particle_count();
  auto& nbrs = work.nbrs;
  // links across components (paper §3.1, Fig. 3)
  for (size_t li = 0; li < spec.links.size(); ++li) {
    const LinkSpec& l = spec.links[li];
    const Component& A = m.components[m.find_component(l.a)];
    const Component& B = m.components[m.find_component(l.b)];
    const bool ra = A.kind == ComponentKind::Rigid, rb = B.kind == ComponentKind::Rigid;
    if (ra && rb)
      throw InputError(spec.file, l.loc.line, "links[" + std::to_string(li) + "]",
                       "two rigid components are linked through an elastic component, not directly");
    int made = 0;
    if (ra || rb) {
      // rigid-elastic: elastic border particles doubled onto the body
      const Component& R = ra ? A : B;
      const Component& E = ra ? B : A;
      std::vector<Vec3> rpts(m.rest_pos.begin() + R.first_particle, m.rest_pos.begin() + R.first_particle + R.particle_count);
      const SpatialGrid grid(rpts, l.distance);
      const RigidBody& body = m.rigid_bodies[R.rigid_body];
      for (int p = E.first_particle; p < E.first_particle + E.particle_count; ++p) {
        bool near = false;
        grid.for_each_within(m.rest_pos[p], l.distance, [&](int, double) { near = true; });
        if (!near || m.inv_mass[p] == 0.0) continue;
        m.attachments.push_back(RigidAttachment{p, R.rigid_body, m.rest_pos[p] - body.com_rest});
        m.inv_mass[p] = 0.0;
        m.locked_axes[p] = 7;
        ++made;
      }
    } else {
      // elastic-elastic: border particles get their nearest neighbours in the other component
      auto connect = [&](const Component& from, const Component& to) {
        std::vector<Vec3> tpts(m.rest_pos.begin() + to.first_particle, m.rest_pos.begin() + to.first_particle + to.particle_count);
        const SpatialGrid grid(tpts, l.distance);
        for (int p = from.first_particle; p < from.first_particle + from.particle_count; ++p) {
          std::vector<std::pair<double, int>> cand;
          grid.for_each_within(m.rest_pos[p], l.distance, [&](int q, double d) { cand.emplace_back(d, q + to.first_particle); });
          std::sort(cand.begin(), cand.end());
          for (size_t c = 0; c < cand.size() && c < 3; ++c) {
            if (nbrs[p].size() >= static_cast<size_t>(kMaxNeighbours)) break;
            nbrs[p].push_back(cand[c].second);
            ++made;
          }
        }
      };
      connect(A, B);
      connect(B, A);
    }
    if (made == 0)
      throw InputError(spec.file, l.loc.line, "links[" + std::to_string(li) + "].distance_mm",
                       "no particles of '" + l.a + "' and '" + l.b + "' are that close: nothing linked");
  }

  // neighbourhoods to CSR; rigid particles carry no shape memory
  m.nbr_start.assign(n + 1, 0);
  for (int p = 0; p < n; ++p) {
    m.nbr_start[p] = static_cast<int>(m.nbr.size());
    if (m.shape_memory[p]) m.nbr.insert(m.nbr.end(), nbrs[p].begin(), nbrs[p].end());
  }
  m.nbr_start[n] = static_cast<int>(m.nbr.size());
}

}  // namespace ps
