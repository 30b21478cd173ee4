#include "render/render_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/model/model.h"
#include "engine/util/error.h"

namespace ps::render {

namespace {
bool contains(const std::string& s, const char* w) { return s.find(w) != std::string::npos; }
}  // namespace

OrganKind organ_kind(const std::string& n0) {
  std::string n = n0;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (contains(n, "prostat")) return OrganKind::Prostate;
  if (contains(n, "bladder")) return OrganKind::Bladder;
  if (contains(n, "rect")) return OrganKind::Rectum;
  if (contains(n, "fat") || contains(n, "skin")) return OrganKind::Fat;
  if (contains(n, "bone") || contains(n, "pubi") || contains(n, "pelv") || contains(n, "arch")) return OrganKind::Bone;
  return OrganKind::Other;
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
  }
  return {};
}

std::string urethra_file_beside(const std::string& mesh) {
  if (mesh.empty()) return {};
  const auto p = std::filesystem::path(mesh).parent_path() / "urethra.csv";
  std::error_code ec;
  return std::filesystem::is_regular_file(p, ec) ? p.string() : std::string();
}

static std::vector<Vec3> read_polyline_mm(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, 0, "urethra", "cannot read the urethra polyline");
  std::vector<Vec3> pts;
  std::string line;
  int ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    if (line.empty() || line[0] == '#' || std::isalpha(static_cast<unsigned char>(line[0]))) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    double x, y, z;
    if (!(ss >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw InputError(file, ln, "urethra", "expected x_mm,y_mm,z_mm");
    pts.emplace_back(x * 1e-3, y * 1e-3, z * 1e-3);
  }
  return pts;
}

RenderScene make_render_scene(const Model& m, const std::string& urethra_csv) {
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
    rs.kind = organ_kind(rs.name);
    rs.colour = organ_colour(rs.kind);
    rs.particles = s.vertices;
    std::vector<int> local(m.particle_count(), -1);
    for (size_t v = 0; v < s.vertices.size(); ++v) local[s.vertices[v]] = static_cast<int>(v);
    rs.indices.reserve(3 * s.faces.size());
    for (const auto& f : s.faces)
      for (int k = 0; k < 3; ++k) rs.indices.push_back(static_cast<uint32_t>(local[f[k]]));
    sc.surfaces.push_back(std::move(rs));
  }
  // the clearest organs last in the list (the renderer sorts transparent ones per view anyway)
  std::stable_sort(sc.surfaces.begin(), sc.surfaces.end(),
                   [](const RenderSurface& a, const RenderSurface& b) { return a.colour.a > b.colour.a; });

  // tags: lesions / tumours red-purple, targets green
  for (size_t t = 0; t < m.tag_names.size() && !m.particle_tags.empty(); ++t) {
    const std::string& n = m.tag_names[t];
    const bool lesion = contains(n, "lesion") || contains(n, "tumo");
    const bool target = contains(n, "target");
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

  const int pc = m.find_component("prostate");
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

  if (!urethra_csv.empty() && pc >= 0) {
    const std::vector<Vec3> pts = read_polyline_mm(urethra_csv);
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

}  // namespace ps::render
