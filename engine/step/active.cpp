// Active components (paper §3.1, muscles): each fibre pair (two neighbours whose rest direction
// lies along the fibre) pulls together with activation * active_force, equal and opposite.
#include "engine/step/stages.h"

namespace ps {

void add_active_forces(const Model& m, State& s) {
  for (const FibrePair& fp : m.fibre_pairs) {
    const double a = s.activation[fp.component];
    if (a <= 0.0) continue;
    const Vec3 d = s.x[fp.b] - s.x[fp.a];
    const double len = d.norm();
    if (len <= 0.0) continue;
    const Vec3 F = (a * m.components[fp.component].active_force / len) * d;
    s.f[fp.a] += F;
    s.f[fp.b] -= F;
  }
}

}  // namespace ps
