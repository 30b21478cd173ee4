#include "render/render_scene.h"

#include <algorithm>
#include <cmath>

#include "engine/model/model.h"

namespace ps::render {

namespace {
bool contains(const std::string& s, const char* w) { return s.find(w) != std::string::npos; }
}  // namespace

OrganKind organ_kind(Role role) {
  switch (role) {
    case Role::Prostate: return OrganKind::Prostate;
    case Role::Bladder: return OrganKind::Bladder;
    case Role::Rectum: return OrganKind::Rectum;
    case Role::Fat:
    case Role::Skin: return OrganKind::Fat;
    case Role::Bone: return OrganKind::Bone;
    default: return OrganKind::Other;
  }
}

// Colours after anatomical atlases (prostate: pink-red gland, bladder: pale straw, rectum:
// brownish mucosa, fat: pale yellow and nearly clear so the gland shows through, bone: ivory).
// Alpha is the default opacity: the prostate is slightly clear so the urethra and lesions inside
// it show.
Rgba organ_colour(OrganKind k) {
  switch (k) {
    case OrganKind::Prostate: return {0.86f, 0.42f, 0.40f, 0.62f};
    case OrganKind::Bladder: return {0.93f, 0.84f, 0.45f, 0.40f};
    case OrganKind::Rectum: return {0.62f, 0.40f, 0.30f, 0.45f};
    case OrganKind::Fat: return {0.98f, 0.90f, 0.62f, 0.10f};
    case OrganKind::Bone: return {0.92f, 0.90f, 0.82f, 1.0f};
    case OrganKind::Other: return {0.70f, 0.70f, 0.75f, 0.8f};
    case OrganKind::SeminalVesicle: return {0.86f, 0.70f, 0.52f, 0.85f};
  }
  return {};
}

RenderScene make_render_scene(const Model& m, const std::vector<anatomy::DisplayMesh>& shapes) {
  RenderScene sc;
  sc.name = m.name;
  sc.particle_count = m.particle_count();
  sc.rest.resize(3 * static_cast<size_t>(m.particle_count()));
  for (int p = 0; p < m.particle_count(); ++p)
    for (int k = 0; k < 3; ++k) sc.rest[3 * p + k] = static_cast<float>(m.rest_pos[p][k]);

  for (const Surface& s : m.surfaces) {
    if (s.component < 0) continue;
    RenderSurface rs;
    rs.name = m.components[s.component].name;
    rs.kind = organ_kind(m.components[s.component].role);
    rs.colour = organ_colour(rs.kind);
    rs.particles = s.vertices;
    std::vector<int> local(m.particle_count(), -1);
    for (size_t v = 0; v < s.vertices.size(); ++v) local[s.vertices[v]] = static_cast<int>(v);
    rs.indices.reserve(3 * s.faces.size());
    for (const auto& f : s.faces)
      for (int k = 0; k < 3; ++k) rs.indices.push_back(static_cast<uint32_t>(local[f[k]]));
    sc.surfaces.push_back(std::move(rs));
  }
  for (const anatomy::DisplayMesh& d : shapes) {
    RenderSurface rs;
    rs.name = d.name;
    rs.kind = d.kind == anatomy::DisplayMesh::Bone ? OrganKind::Bone : OrganKind::SeminalVesicle;
    rs.colour = organ_colour(rs.kind);
    // the symphysis lies in front of the gland: drawn half-clear so that the anterior view still
    // shows the prostate (the physical arch under it stays opaque)
    if (d.kind == anatomy::DisplayMesh::Bone) rs.colour.a = 0.5f;
    rs.carry_particles = d.carriers;
    rs.carry_weights = d.weights;
    rs.carry_offsets = d.offsets;
    for (const Vec3& v : d.mesh.vertices)
      for (int k = 0; k < 3; ++k) rs.carry_rest.push_back(static_cast<float>(v[k]));
    for (const auto& f : d.mesh.faces)
      for (int k = 0; k < 3; ++k) rs.indices.push_back(static_cast<uint32_t>(f[k]));
    sc.surfaces.push_back(std::move(rs));
  }
  // the clearest organs last in the list (the renderer sorts transparent ones per view anyway)
  std::stable_sort(sc.surfaces.begin(), sc.surfaces.end(),
                   [](const RenderSurface& a, const RenderSurface& b) { return a.colour.a > b.colour.a; });

  // tags: lesions / tumours red-purple, targets green
  for (size_t t = 0; t < m.tag_names.size() && !m.particle_tags.empty(); ++t) {
    const std::string& n = m.tag_names[t];
    const bool lesion = m.tag_role(static_cast<int>(t)) == Role::Lesion;
    const bool target = !lesion && contains(n, "target");  // a zone to aim at, drawn, not an organ
    if (!lesion && !target) continue;
    RenderMarkers mk;
    mk.name = n;
    mk.role = lesion ? DrawRole::Lesion : DrawRole::Target;
    mk.colour = lesion ? Rgba{0.55f, 0.05f, 0.35f, 1.0f} : Rgba{0.10f, 0.75f, 0.25f, 1.0f};
    double h = 0.0;
    for (int p = 0; p < m.particle_count(); ++p)
      if (m.particle_tags[p] >> t & 1ull) {
        mk.particles.push_back(p);
        h = std::max(h, m.components[m.component_of[p]].spacing);
      }
    // a lesion is a small blob to find: near-touching balls; a target zone covers much of the
    // gland: small dots on its particles, so the gland and the needles inside stay visible
    mk.radius = lesion ? std::max(1.5e-3, 0.45 * h) : std::max(1.0e-3, 0.2 * h);
    if (!mk.particles.empty()) sc.markers.push_back(std::move(mk));
  }

  const int pc = m.find_role(Role::Prostate);
  Vec3 lo = Vec3::Constant(1e9), hi = Vec3::Constant(-1e9);
  const int fc = pc >= 0 ? pc : -1;
  for (int p = 0; p < m.particle_count(); ++p) {
    if (fc >= 0 && m.component_of[p] != fc) continue;
    lo = lo.cwiseMin(m.rest_pos[p]);
    hi = hi.cwiseMax(m.rest_pos[p]);
  }
  if (m.particle_count() > 0) {
    sc.focus = 0.5 * (lo + hi);
    // a prostate is framed with its neighbours (rectum, bladder neck): 2.2x its half-size
    sc.extent = std::max(0.01, (fc >= 0 ? 2.2 : 0.6) * 0.5 * (hi - lo).norm());
  }

  if (m.urethra.size() >= 2 && pc >= 0) {
    const std::vector<Vec3>& pts = m.urethra;
    const Component& c = m.components[pc];
    RenderTube tube;
    tube.name = "urethra";
    tube.colour = {0.98f, 0.85f, 0.20f, 1.0f};
    tube.radius = 2.5e-3;
    for (const Vec3& q : pts) {
      // 4 nearest prostate particles at rest
      std::array<std::pair<double, int>, 4> best;
      best.fill({1e30, c.first_particle});
      for (int p = c.first_particle; p < c.first_particle + c.particle_count; ++p) {
        const double d = (m.rest_pos[p] - q).squaredNorm();
        if (d < best[3].first) {
          best[3] = {d, p};
          std::sort(best.begin(), best.end());
        }
      }
      std::array<int, 4> ids;
      std::array<float, 4> w;
      double ws = 0.0;
      Vec3 centre = Vec3::Zero();
      for (int k = 0; k < 4; ++k) ws += 1.0 / (std::sqrt(best[k].first) + 1e-4);
      for (int k = 0; k < 4; ++k) {
        ids[k] = best[k].second;
        w[k] = static_cast<float>(1.0 / (std::sqrt(best[k].first) + 1e-4) / ws);
        centre += w[k] * m.rest_pos[ids[k]];
      }
      tube.particles.push_back(ids);
      tube.weights.push_back(w);
      tube.offsets.push_back(q - centre);
    }
    if (tube.particles.size() >= 2) sc.tubes.push_back(std::move(tube));
  }
  return sc;
}

RenderScene make_render_scene(const ScenarioSpec& spec, const Model& m) {
  return make_render_scene(m, anatomy::display_meshes_for_scenario(spec, m));
}

}  // namespace ps::render
