// Constraints stage of compile_scenario: fixed axes, imposed displacements, half-spaces and
// applied forces, each on the particles its region selects (rigid particles never).
#include <string>
#include <vector>

#include "engine/scenario/compile_stages.h"
#include "engine/util/error.h"

namespace ps {

void compile_constraints(const ScenarioSpec& spec, Model& m) {
  const int n = m.particle_count();
  // constraints and applied forces
  for (size_t ki = 0; ki < spec.constraints.size(); ++ki) {
    const ConstraintSpec& c = spec.constraints[ki];
    const std::string key = "constraints[" + std::to_string(ki) + "]";
    std::vector<int> sel;
    for (int p = 0; p < n; ++p) {
      if (!c.component.empty() && m.components[m.component_of[p]].name != c.component) continue;
      if (m.components[m.component_of[p]].kind == ComponentKind::Rigid) continue;
      if (c.kind == ConstraintSpec::HalfSpace || c.region.contains(m.rest_pos[p])) sel.push_back(p);
    }
    if (sel.empty()) throw InputError(spec.file, c.loc.line, key + ".region", "selects no particle");
    switch (c.kind) {
      case ConstraintSpec::Fix:
        for (int p : sel) { m.fixed.push_back({p, c.axes}); m.locked_axes[p] |= c.axes; }
        break;
      case ConstraintSpec::Displace:
        m.imposed.push_back(ImposedDisplacement{sel, c.by, c.axes, c.t0, c.t1});
        for (int p : sel) m.locked_axes[p] |= c.axes;
        break;
      case ConstraintSpec::HalfSpace: {
        for (int p : sel)
          if ((m.rest_pos[p] - c.region.point).dot(c.region.normal) < -1e-9)
            throw InputError(spec.file, c.loc.line, key + ".point_mm",
                             "particle " + std::to_string(p) + " starts outside the allowed half-space");
        m.half_spaces.push_back(HalfSpace{sel, c.region.point, c.region.normal});
        break;
      }
      case ConstraintSpec::Force: m.applied_forces.push_back(AppliedForce{sel, c.by, c.t0, c.t1}); break;
    }
  }
}

}  // namespace ps
