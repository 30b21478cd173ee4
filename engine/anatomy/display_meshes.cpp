#include "engine/anatomy/display_meshes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>

#include "engine/mesh/mesh_import.h"

namespace ps::anatomy {

namespace {

const char* units_of(double unit_scale) {
  if (std::abs(unit_scale - 1e-3) < 1e-12) return "mm";
  if (std::abs(unit_scale - 1e-2) < 1e-12) return "cm";
  if (std::abs(unit_scale - 1e-1) < 1e-12) return "dm";
  return "m";
}

// Binds every vertex of `d.mesh` to its 4 nearest particles at rest among those for which `use(p)`
// is true (carry_vertex).
template <class Use>
void carry_by_particles(DisplayMesh& d, const Model& m, Use use) {
  d.carriers.clear();
  d.weights.clear();
  d.offsets.clear();
  std::vector<int> candidates;
  for (int p = 0; p < m.particle_count(); ++p)
    if (use(p)) candidates.push_back(p);
  for (const Vec3& q : d.mesh.vertices) {
    const CarriedVertex c = carry_vertex(q, m.rest_pos, candidates);
    d.carriers.push_back(c.ids);
    d.weights.push_back(c.weights);
    d.offsets.push_back(c.offset);
  }
}

}  // namespace

CarriedVertex carry_vertex(const Vec3& q, const std::vector<Vec3>& rest, const std::vector<int>& candidates) {
  std::array<std::pair<double, int>, 4> best;
  best.fill({1e300, candidates.empty() ? 0 : candidates.front()});
  for (int p : candidates) {
    const double d2 = (rest[p] - q).squaredNorm();
    if (d2 < best[3].first) {
      best[3] = {d2, p};
      std::sort(best.begin(), best.end());
    }
  }
  CarriedVertex c;
  double ws = 0.0;
  for (int k = 0; k < 4; ++k) ws += 1.0 / (std::sqrt(best[k].first) + 1e-4);
  Vec3 centre = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    c.ids[k] = best[k].second;
    c.weights[k] = static_cast<float>(1.0 / (std::sqrt(best[k].first) + 1e-4) / ws);
    centre += static_cast<double>(c.weights[k]) * rest[c.ids[k]];  // the float weights the views use
  }
  c.offset = q - centre;
  return c;
}

std::vector<TriMesh> connected_parts(const TriMesh& mesh) {
  const int nv = static_cast<int>(mesh.vertices.size());
  std::vector<int> root(nv);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  for (const auto& f : mesh.faces)
    for (int k = 1; k < 3; ++k) root[find(f[k])] = find(f[0]);
  std::vector<int> part_of_root(nv, -1), local(nv, -1);
  std::vector<TriMesh> parts;
  for (const auto& f : mesh.faces) {
    const int r = find(f[0]);
    if (part_of_root[r] < 0) part_of_root[r] = static_cast<int>(parts.size()), parts.emplace_back();
    TriMesh& t = parts[part_of_root[r]];
    std::array<int, 3> g;
    for (int k = 0; k < 3; ++k) {
      if (local[f[k]] < 0) local[f[k]] = static_cast<int>(t.vertices.size()), t.vertices.push_back(mesh.vertices[f[k]]);
      g[k] = local[f[k]];
    }
    t.faces.push_back(g);
  }
  return parts;
}


std::vector<DisplayMesh> display_meshes_for_scenario(const ScenarioSpec& spec, const Model& m) {
  std::vector<DisplayMesh> out;
  const int gland = spec.prostate_zones ? m.find_component(spec.prostate_zones->component) : m.find_role(Role::Prostate);
  if (gland < 0 || static_cast<size_t>(gland) >= spec.components.size() || m.particle_count() == 0) return out;
  const ComponentSpec& c = spec.components[static_cast<size_t>(gland)];
  if (c.shape.kind != ShapeSpec::Mesh || c.shape.mesh.file.empty()) return out;
  const std::filesystem::path dir = std::filesystem::path(c.shape.mesh.file).parent_path();
  MeshImportOptions place;
  place.units = units_of(c.shape.mesh.unit_scale);
  place.scale = c.shape.mesh.scale;
  place.rotate_deg = c.shape.mesh.rotate_deg;
  place.translate_m = c.shape.mesh.translate;
  std::error_code ec;
  // vesicles: carried by the deformable tissue (not rigid or kinematic particles)
  const std::filesystem::path sv = dir / "seminal_vesicles.obj";
  if (std::filesystem::is_regular_file(sv, ec)) {
    for (TriMesh& part : connected_parts(import_mesh(sv.string(), place))) {
      DisplayMesh d;
      Vec3 centre = Vec3::Zero();
      for (const Vec3& v : part.vertices) centre += v;
      centre /= static_cast<double>(std::max<size_t>(1, part.vertices.size()));
      d.name = centre.x() >= 0.0 ? "seminal_vesicle_right" : "seminal_vesicle_left";
      d.kind = DisplayMesh::SeminalVesicle;
      d.mesh = std::move(part);
      carry_by_particles(d, m, [&](int p) { return m.components[m.component_of[p]].kind != ComponentKind::Rigid; });
      out.push_back(std::move(d));
    }
  }
  const std::filesystem::path bone = dir / "pubic_bone.obj";
  if (std::filesystem::is_regular_file(bone, ec)) {
    DisplayMesh d;
    d.name = "pubic_bone";
    d.kind = DisplayMesh::Bone;
    d.mesh = import_mesh(bone.string(), place);
    const int b = m.find_role(Role::Bone);
    carry_by_particles(d, m, [&](int p) { return b < 0 || m.component_of[p] == b; });
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace ps::anatomy
