// Local constraints (paper §3.1): applied to single particles by direct projection.
#include <algorithm>

#include "engine/step/stages.h"

namespace ps {

double ramp_fraction(double t, double t0, double t1);  // forces.cpp

void apply_imposed_displacements(const Model& m, State& s, double t) {
  for (const ImposedDisplacement& d : m.imposed) {
    const Vec3 u = ramp_fraction(t, d.t0, d.t1) * d.by;
    for (int p : d.particles)
      for (int a = 0; a < 3; ++a)
        if (d.axes & (1u << a)) s.x[p][a] = m.rest_pos[p][a] + u[a];
  }
}

void apply_local_constraints(const Model& m, State& s, double t) {
  for (const FixedParticle& fp : m.fixed)
    for (int a = 0; a < 3; ++a)
      if (fp.axes & (1u << a)) s.x[fp.particle][a] = m.rest_pos[fp.particle][a];
  apply_imposed_displacements(m, s, t);
  for (const HalfSpace& h : m.half_spaces) {
    for (int p : h.particles) {
      const double depth = (s.x[p] - h.point).dot(h.normal);
      if (depth < 0.0) {
        s.x[p] -= depth * h.normal;
        s.contact[p] = 7;
      }
    }
  }
}

}  // namespace ps
