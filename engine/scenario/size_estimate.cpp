#include "engine/scenario/size_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/mesh/mesh_import.h"
#include "engine/util/error.h"

namespace ps {

namespace {

std::string human(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

// Lattice points of an axis-aligned box of extent e at spacing h, volumetric or its shell.
double lattice_points(const Vec3& e, double h, bool volumetric) {
  double n[3];
  for (int a = 0; a < 3; ++a) n[a] = std::max(1.0, std::round(e[a] / h)) + 1.0;
  const double all = n[0] * n[1] * n[2];
  if (volumetric) return all;
  const double inner = std::max(0.0, n[0] - 2) * std::max(0.0, n[1] - 2) * std::max(0.0, n[2] - 2);
  return all - inner;
}

}  // namespace

SizeEstimate estimate_component_size(const ComponentSpec& c, const std::string& file) {
  const ShapeSpec& s = c.shape;
  const double h = c.spacing;
  double n = 0.0;
  switch (s.kind) {
    case ShapeSpec::Box:
      n = lattice_points(s.max - s.min, h, c.volumetric);
      break;
    case ShapeSpec::Cylinder: {
      const double pi = 3.14159265358979;
      const double side = 2 * pi * s.radius * s.length / (h * h), caps = 2 * pi * s.radius * s.radius / (h * h);
      n = side + caps + (c.volumetric ? pi * s.radius * s.radius * s.length / (h * h * h) : 0.0);
      break;
    }
    case ShapeSpec::Mesh: {
      // The import itself is bounded (kMaxImportFaces, kMaxImportFileBytes); what spacing drives is
      // the remesh and the fill, estimated from the placed mesh's bounding box.
      MeshImportOptions opt;
      opt.units = s.mesh.unit_scale == 1.0 ? "m" : s.mesh.unit_scale == 1e-1 ? "dm" : s.mesh.unit_scale == 1e-2 ? "cm" : "mm";
      opt.scale = s.mesh.scale;
      opt.rotate_deg = s.mesh.rotate_deg;
      opt.translate_m = s.mesh.translate;
      const TriMesh m = import_mesh(s.mesh.file, opt);
      Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
      for (const Vec3& v : m.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
      n = m.vertices.empty() ? 0.0 : lattice_points(hi - lo, h, c.volumetric);
      break;
    }
  }
  return {n, n * kBytesPerParticle};
}

SizeEstimate check_scenario_size(const ScenarioSpec& spec, const ScenarioLimits& limits) {
  SizeEstimate total;
  std::vector<SizeEstimate> per(spec.components.size());
  for (size_t i = 0; i < spec.components.size(); ++i) {
    per[i] = estimate_component_size(spec.components[i], spec.file);
    total.particles += per[i].particles;
    total.bytes += per[i].bytes;
  }
  if (total.particles <= limits.max_particles && total.bytes <= limits.max_bytes) return total;
  // Name the component that contributes most and the spacing that brings the whole scene within
  // the limit (particles scale as 1/h^3 for a volumetric fill, 1/h^2 for a surface).
  size_t worst = 0;
  for (size_t i = 1; i < per.size(); ++i)
    if (per[i].particles > per[worst].particles) worst = i;
  const ComponentSpec& c = spec.components[worst];
  const double over = std::max(total.particles / limits.max_particles, total.bytes / limits.max_bytes);
  const double others = total.particles - per[worst].particles;
  const double allowed = std::max(1.0, std::min(limits.max_particles, limits.max_bytes / kBytesPerParticle) - others);
  const double ratio = std::max(over, per[worst].particles / allowed);
  const double need = c.spacing * std::pow(ratio, c.volumetric ? 1.0 / 3.0 : 0.5) * 1.05;
  throw InputError(spec.file, c.loc.line, "components[" + std::to_string(worst) + "].spacing_mm",
                   "the scene would have about " + human(total.particles) + " particles (~" +
                       human(total.bytes / (1u << 20)) + " MiB), over the limit of " + human(limits.max_particles) +
                       " particles / " + human(limits.max_bytes / (1u << 30)) + " GiB; component '" + c.name +
                       "' alone has ~" + human(per[worst].particles) + " at spacing_mm " + human(c.spacing * 1e3) +
                       ": raise its spacing_mm to at least " + human(need * 1e3));
}

}  // namespace ps
