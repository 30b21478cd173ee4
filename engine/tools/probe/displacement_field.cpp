#include "engine/tools/probe/displacement_field.h"

#include <algorithm>
#include <cstdio>

#include "engine/util/atomic_file.h"

namespace ps {

namespace {
const char* const kZoneNames[3] = {"apex", "mid", "base"};

void add(ZoneStats& z, const Vec3& u) {
  const double n = u.norm();
  ++z.count;
  z.mean += n;
  z.max = std::max(z.max, n);
  z.mean_vec += u;
}
void finish(ZoneStats& z) {
  if (z.count == 0) return;
  z.mean /= z.count;
  z.mean_vec /= z.count;
}
}  // namespace

std::vector<int> si_zones(const Model& m, int component, const std::vector<Vec3>& x_ref, const Vec3& superior) {
  const Component& c = m.components.at(component);
  const Vec3 up = superior.normalized();
  double lo = 1e300, hi = -1e300;
  for (int p = c.first_particle; p < c.first_particle + c.particle_count; ++p) {
    const double s = x_ref[p].dot(up);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  std::vector<int> zone(c.particle_count, 1);
  const double span = hi - lo;
  if (!(span > 0.0)) return zone;
  for (int k = 0; k < c.particle_count; ++k) {
    const double f = (x_ref[c.first_particle + k].dot(up) - lo) / span;  // 0 apex .. 1 base
    zone[k] = f < 1.0 / 3.0 ? 0 : (f > 2.0 / 3.0 ? 2 : 1);
  }
  return zone;
}

DisplacementStats displacement_stats(const Model& m, int component, const std::vector<Vec3>& x_ref,
                                     const std::vector<Vec3>& x, const Vec3& superior) {
  DisplacementStats d;
  d.all.name = "all";
  ZoneStats* zs[3] = {&d.apex, &d.mid, &d.base};
  for (int z = 0; z < 3; ++z) zs[z]->name = kZoneNames[z];
  const Component& c = m.components.at(component);
  const std::vector<int> zone = si_zones(m, component, x_ref, superior);
  for (int k = 0; k < c.particle_count; ++k) {
    const int p = c.first_particle + k;
    const Vec3 u = x[p] - x_ref[p];
    add(d.all, u);
    add(*zs[zone[k]], u);
  }
  finish(d.all);
  for (ZoneStats* z : zs) finish(*z);
  return d;
}

std::string displacement_csv(const Model& m, int component, const std::vector<Vec3>& x_ref, const std::vector<Vec3>& x,
                             const Vec3& superior) {
  std::string out = "id,component,zone,x0_mm,y0_mm,z0_mm,x_mm,y_mm,z_mm,ux_mm,uy_mm,uz_mm,u_mm\n";
  char line[320];
  const int nc = static_cast<int>(m.components.size());
  for (int c = 0; c < nc; ++c) {
    if (component >= 0 && c != component) continue;
    const Component& comp = m.components[c];
    const std::vector<int> zone = si_zones(m, c, x_ref, superior);
    for (int k = 0; k < comp.particle_count; ++k) {
      const int p = comp.first_particle + k;
      const Vec3 a = x_ref[p] * 1e3, b = x[p] * 1e3, u = b - a;
      std::snprintf(line, sizeof line, "%d,%s,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", p, comp.name.c_str(),
                    kZoneNames[zone[k]], a[0], a[1], a[2], b[0], b[1], b[2], u[0], u[1], u[2], u.norm());
      out += line;
    }
  }
  return out;
}

void write_displacement_csv(const std::string& path, const Model& m, int component, const std::vector<Vec3>& x_ref,
                            const std::vector<Vec3>& x, const Vec3& superior) {
  write_file_atomic(path, displacement_csv(m, component, x_ref, x, superior));
}

}  // namespace ps
