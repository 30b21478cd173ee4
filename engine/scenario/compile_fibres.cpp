// Fibres stage of compile_scenario: the contracting pairs of active components.
#include <cmath>

#include "engine/scenario/compile_stages.h"

namespace ps {

void compile_fibres(Model& m) {
  // active fibres: neighbour pairs whose rest direction is within 30 degrees of the fibre
  for (size_t ci = 0; ci < m.components.size(); ++ci) {
    const Component& comp = m.components[ci];
    if (comp.kind != ComponentKind::Active) continue;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p)
      for (int a = m.nbr_start[p]; a < m.nbr_start[p + 1]; ++a) {
        const int q = m.nbr[a];
        if (q <= p || m.component_of[q] != static_cast<int>(ci)) continue;
        const Vec3 d = (m.rest_pos[q] - m.rest_pos[p]).normalized();
        if (std::abs(d.dot(comp.fibre_dir)) > std::cos(30.0 * 3.14159265358979 / 180.0))
          m.fibre_pairs.push_back(FibrePair{p, q, static_cast<int>(ci)});
      }
  }
}

}  // namespace ps
