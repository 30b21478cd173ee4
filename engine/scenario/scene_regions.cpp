#include "engine/scenario/scene_regions.h"

#include <cstdio>
#include <memory>

#include "engine/anatomy/zones.h"
#include "engine/mesh/mesh_query.h"
#include "engine/scenario/shape_mesh.h"
#include "engine/util/error.h"

namespace ps::anatomy {

namespace {

std::string mm_point(const Vec3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f) mm", p.x() * 1e3, p.y() * 1e3, p.z() * 1e3);
  return buf;
}

// The closed outward surface a volumetric fill of this component starts from.
TriMesh component_surface(const ComponentSpec& c, const std::string& file) {
  const ShapeSpec& s = c.shape;
  switch (s.kind) {
    case ShapeSpec::Box: {
      const ParticleSet b = box_particles(s.min, s.max, c.spacing, false);
      return TriMesh{b.pos, b.faces};
    }
    case ShapeSpec::Cylinder: return cylinder_surface(s.base, s.axis, s.radius, s.length, c.spacing);
    case ShapeSpec::Mesh: return load_component_surface(c, file, c.spacing);
  }
  return {};
}

size_t spec_index(const ScenarioSpec& spec, const std::string& name) {
  size_t j = 0;
  while (spec.components[j].name != name) ++j;  // names checked by the parser
  return j;
}

}  // namespace

ParticleSet fill_excluding(const ScenarioSpec& spec, size_t ci, const std::vector<ParticleSet>& sets,
                           double* excluded_volume) {
  const ComponentSpec& c = spec.components[ci];
  const std::string key = "components." + c.name + ".exclude_inside";
  const TriMesh surf = component_surface(c, spec.file);
  const MeshQuery own(surf);
  std::vector<std::unique_ptr<MeshQuery>> others;
  double vol = 0.0;
  for (const std::string& name : c.exclude_inside) {
    const size_t j = spec_index(spec, name);
    const TriMesh other{sets[j].pos, sets[j].faces};
    for (const Vec3& v : other.vertices)
      if (!own.inside(v))
        throw InputError(spec.file, c.loc.line, key,
                         "'" + name + "' is not inside '" + c.name + "': its particle at " + mm_point(v) + " lies outside");
    vol += signed_volume(other);
    others.push_back(std::make_unique<MeshQuery>(other));
  }
  // the excluded organs must not intersect one another (a misplaced or wrongly scaled mesh): a
  // particle of one inside another would be claimed by two organs and their volumes counted twice
  for (size_t j = 0; j < others.size(); ++j) {
    const ParticleSet& a = sets[spec_index(spec, c.exclude_inside[j])];
    for (size_t k = 0; k < others.size(); ++k) {
      if (k == j) continue;
      for (const Vec3& v : a.pos)
        if (others[k]->inside(v))
          throw InputError(spec.file, c.loc.line, key,
                           "'" + c.exclude_inside[j] + "' and '" + c.exclude_inside[k] + "' overlap: the particle of '" +
                               c.exclude_inside[j] + "' at " + mm_point(v) + " lies inside '" + c.exclude_inside[k] +
                               "' (check their meshes' units, scale and translate_mm)");
    }
  }
  for (const Vec3& v : surf.vertices)
    for (size_t k = 0; k < others.size(); ++k)
      if (others[k]->inside(v))
        throw InputError(spec.file, c.loc.line, key,
                         "the surface of '" + c.name + "' passes through '" + c.exclude_inside[k] + "' at " + mm_point(v));
  const double margin = 0.45 * c.spacing;
  auto excluded = [&](const Vec3& p) {
    for (const auto& q : others)
      if (q->inside(p) || q->distance(p) < margin) return true;
    return false;
  };
  if (excluded_volume) *excluded_volume = vol;
  return volumetric_particles(
      surf, c.spacing, [&](const Vec3& p) { return own.inside(p) && !excluded(p); },
      [&](const Vec3& p) { return own.distance(p); });
}

namespace {

uint64_t splitmix64(uint64_t& x) {
  uint64_t z = (x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

std::vector<Vec3> seeded_lesion_centres(const ScenarioSpec& spec, const Model& m) {
  const LesionsSpec& ls = *spec.lesions;
  const Component& comp = m.components[m.find_component(spec.prostate_zones->component)];
  const int zone = m.find_tag(ls.zone);
  std::vector<int> cand;
  for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p)
    if (zone >= 0 && (m.particle_tags[p] >> zone & 1u)) cand.push_back(p);
  if (cand.empty()) throw InputError(spec.file, ls.loc.line, "lesions.zone", "no particle of the gland lies in zone '" + ls.zone + "'");
  uint64_t state = ls.seed;
  std::vector<Vec3> centres;
  for (int k = 0; k < ls.count; ++k) {
    Vec3 c = Vec3::Zero();
    bool placed = false;
    for (int attempt = 0; attempt < 1000 && !placed; ++attempt) {
      c = m.rest_pos[cand[splitmix64(state) % cand.size()]];
      placed = true;
      for (const Vec3& o : centres) placed &= (o - c).norm() >= ls.diameter;
    }
    if (!placed)
      throw InputError(spec.file, ls.loc.line, "lesions.count",
                       std::to_string(ls.count) + " lesions of " + std::to_string(ls.diameter * 1e3) + " mm do not fit a diameter apart in zone '" + ls.zone + "'");
    centres.push_back(c);
  }
  return centres;
}

namespace {

// `lesions:`: spheres on particles of the zone drawn from the seed, a diameter apart (LesionsSpec)
void place_lesions(const ScenarioSpec& spec, Model& m) {
  const LesionsSpec& ls = *spec.lesions;
  const Component& comp = m.components[m.find_component(spec.prostate_zones->component)];
  const std::vector<Vec3> centres = seeded_lesion_centres(spec, m);
  for (int k = 0; k < ls.count; ++k) {
    const Vec3& c = centres[static_cast<size_t>(k)];
    if (m.tag_names.size() >= 64) throw InputError(spec.file, ls.loc.line, "lesions", "more than 64 tags (zones included)");
    const std::string name = "lesion_" + std::to_string(k + 1);
    if (m.find_tag(name) >= 0) throw InputError(spec.file, ls.loc.line, "lesions", "tag '" + name + "' is already given under tags:");
    const int bit = static_cast<int>(m.tag_names.size());
    m.tag_names.push_back(name);
    m.tag_roles.push_back(Role::Lesion);
    const double r = 0.5 * ls.diameter;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p)
      if ((m.rest_pos[p] - c).norm() <= r) m.particle_tags[p] |= uint64_t{1} << bit;
  }
}

}  // namespace

void apply_particle_tags(const ScenarioSpec& spec, Model& m, const std::vector<std::vector<std::array<int, 3>>>& faces_of) {
  if (!spec.prostate_zones && spec.tags.empty()) return;
  const int n = m.particle_count();
  m.particle_tags.assign(n, 0);
  if (spec.prostate_zones) {
    const ZonesSpec& z = *spec.prostate_zones;
    const int ci = m.find_component(z.component);
    const Component& comp = m.components[ci];
    if (!comp.volumetric || faces_of[ci].empty())
      throw InputError(spec.file, z.loc.line, "prostate_zones.component",
                       "'" + z.component + "' must be a volumetric component with a closed surface");
    for (const char* t : kZoneTagNames) {
      m.tag_names.emplace_back(t);
      m.tag_roles.push_back(Role::Other);  // a zone of the gland, not an organ
    }
    // depth below the capsule from the component's own rest surface
    TriMesh surf;
    surf.vertices = m.rest_pos;
    surf.faces = faces_of[ci];
    const MeshQuery q(surf);
    const std::vector<Vec3> pts(m.rest_pos.begin() + comp.first_particle,
                                m.rest_pos.begin() + comp.first_particle + comp.particle_count);
    const ProstateFrame frame = ProstateFrame::from_points(pts, z.peripheral_depth);
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      const double depth = m.on_surface[p] ? 0.0 : q.distance(m.rest_pos[p]);
      for (int t : zone_tag_indices(classify_prostate_point(m.rest_pos[p], depth, frame)))
        m.particle_tags[p] |= uint64_t{1} << t;
    }
  }
  for (size_t i = 0; i < spec.tags.size(); ++i) {
    const TagSpec& t = spec.tags[i];
    const std::string key = "tags[" + std::to_string(i) + "]";
    if (m.find_tag(t.name) >= 0)
      throw InputError(spec.file, t.loc.line, key + ".name", "'" + t.name + "' is a prostate zone name");
    if (m.tag_names.size() >= 64) throw InputError(spec.file, t.loc.line, key, "more than 64 tags (zones included)");
    const int bit = static_cast<int>(m.tag_names.size());
    m.tag_names.push_back(t.name);
    m.tag_roles.push_back(resolve_role(t.role, t.name, false));
    const Component& comp = m.components[m.find_component(t.component)];
    int hits = 0;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p)
      if (t.region.contains(m.rest_pos[p])) {
        m.particle_tags[p] |= uint64_t{1} << bit;
        ++hits;
      }
    if (hits == 0)
      throw InputError(spec.file, t.loc.line, key + ".region", "selects no particle of component '" + t.component + "'");
  }
  if (spec.lesions) place_lesions(spec, m);
}

}  // namespace ps::anatomy
