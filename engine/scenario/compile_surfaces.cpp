// Surfaces stage of compile_scenario: one closed surface per component with its rest volume,
// volume-constrained when the material is incompressible; a zero-area face is a CompileError.
#include <algorithm>
#include <string>
#include <vector>

#include "engine/scenario/compile_stages.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"

namespace ps {

void compile_surfaces(const ScenarioSpec& spec, Model& m, const CompileWork& work) {
  const auto& faces_of = work.faces_of;
  // surfaces: one per component; volume-constrained when the material is incompressible
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    const MaterialSpec& mat = find_material(spec, spec.components[ci].material);
    Surface s;
    s.component = static_cast<int>(ci);
    s.faces = faces_of[ci];
    std::vector<int> verts;
    for (const auto& f : s.faces) verts.insert(verts.end(), f.begin(), f.end());
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    s.vertices = verts;
    for (const auto& f : s.faces) {
      const Vec3 cr = (m.rest_pos[f[1]] - m.rest_pos[f[0]]).cross(m.rest_pos[f[2]] - m.rest_pos[f[0]]);
      if (!(cr.norm() > 0.0))
        throw CompileError("component '" + spec.components[ci].name + "': zero-area surface face (" +
                           std::to_string(f[0]) + ", " + std::to_string(f[1]) + ", " + std::to_string(f[2]) + ")");
    }
    s.rest_volume = surface_volume(s, m.rest_pos);
    s.volume_constrained = mat.incompressible && m.components[ci].kind != ComponentKind::Rigid;
    m.components[ci].surface = static_cast<int>(m.surfaces.size());
    m.surfaces.push_back(std::move(s));
  }
}

}  // namespace ps
