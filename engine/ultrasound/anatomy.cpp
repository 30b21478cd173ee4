#include "engine/ultrasound/anatomy.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>

#include "engine/model/role.h"
#include "engine/util/error.h"

namespace ps::us {

namespace {

// volume enclosed by faces over positions [m^3] (divergence theorem)
double enclosed_volume(const std::vector<Vec3>& x, const std::vector<std::array<int, 3>>& faces) {
  double v = 0.0;
  for (const auto& f : faces) v += x[f[0]].dot(x[f[1]].cross(x[f[2]])) / 6.0;
  return std::abs(v);
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Loop subdivision of a closed triangle surface, `levels` times (Loop 1987): each edge gets a new
// vertex 3/8 (a + b) + 1/8 (c + d) (c, d opposite it), each old vertex moves to
// (1 - n beta) v + beta sum(neighbours), beta = 3/16 (n = 3) or 3/(8n); each face becomes four.
void loop_subdivide(std::vector<Vec3>& v, std::vector<std::array<int, 3>>& f, int levels) {
  for (int l = 0; l < levels; ++l) {
    const int nv = static_cast<int>(v.size());
    std::map<std::pair<int, int>, std::array<int, 3>> edges;  // (a < b) -> new vertex, opposite vertices c, d
    for (const auto& t : f)
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
        auto [it, fresh] = edges.try_emplace(std::minmax(a, b), std::array<int, 3>{-1, c, -1});
        if (!fresh) it->second[2] = c;
      }
    std::vector<std::vector<int>> nbr(nv);
    std::vector<Vec3> out(v);
    for (auto& [e, d] : edges) {
      nbr[e.first].push_back(e.second);
      nbr[e.second].push_back(e.first);
      d[0] = static_cast<int>(out.size());
      out.push_back(d[2] >= 0 ? Vec3(0.375 * (v[e.first] + v[e.second]) + 0.125 * (v[d[1]] + v[d[2]]))
                              : Vec3(0.5 * (v[e.first] + v[e.second])));
    }
    for (int i = 0; i < nv; ++i) {
      const double n = static_cast<double>(nbr[i].size());
      if (n < 3) continue;
      const double beta = n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
      Vec3 s = Vec3::Zero();
      for (int j : nbr[i]) s += v[j];
      out[i] = (1.0 - n * beta) * v[i] + beta * s;
    }
    std::vector<std::array<int, 3>> g;
    g.reserve(4 * f.size());
    for (const auto& t : f) {
      const int ab = edges[std::minmax(t[0], t[1])][0], bc = edges[std::minmax(t[1], t[2])][0], ca = edges[std::minmax(t[2], t[0])][0];
      g.push_back({t[0], ab, ca});
      g.push_back({t[1], bc, ab});
      g.push_back({t[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    v = std::move(out);
    f = std::move(g);
  }
}

// Appends the vertices `v` (rest positions) as carried vertices of `a`, each carried by its 4
// nearest particles among `carriers` (inverse-distance weights, offset to the vertex); returns the
// index the first one has in a component's faces.
int add_carried(UltrasoundAnatomy& a, const std::vector<Vec3>& rest, const std::vector<Vec3>& v, const std::vector<int>& carriers) {
  const int base = static_cast<int>(rest.size() + a.carried_particles.size());
  for (const Vec3& q : v) {
    const anatomy::CarriedVertex c = anatomy::carry_vertex(q, rest, carriers);
    a.carried_particles.push_back(c.ids);
    a.carried_weights.push_back(c.weights);
    a.carried_offsets.push_back(c.offset);
  }
  return base;
}

}  // namespace

Tissue tissue_for_component(const Component& c) {
  switch (c.role) {
    case Role::Prostate: return Tissue::Prostate;
    case Role::Bladder: return Tissue::Bladder;
    case Role::Rectum: return Tissue::Rectum;
    case Role::Gas: return Tissue::Gas;
    case Role::Bone: return Tissue::Bone;
    case Role::Fat: return Tissue::Fat;
    default: return Tissue::Soft;
  }
}

float prostate_particle_echo(const Model& m, int p) {
  if (m.particle_tags.empty()) return 0.9f;
  const uint64_t t = m.particle_tags[p];
  for (size_t k = 0; k < m.tag_names.size(); ++k)
    if ((t >> k & 1u) && m.tag_role(static_cast<int>(k)) == Role::Lesion) return 0.3f;
  auto tagged = [&](const char* name) {
    const int k = m.find_tag(name);
    return k >= 0 && (t >> k & 1u);
  };
  if (tagged("peripheral")) return 1.0f;
  if (tagged("transition")) return 0.75f;
  if (tagged("anterior")) return 0.55f;
  return 0.9f;
}

UltrasoundAnatomy build_anatomy(const Model& m, const AnatomyOptions& opt) {
  UltrasoundAnatomy a;
  a.rest = m.rest_pos;
  for (size_t t = 0; t < m.tag_names.size() && !m.particle_tags.empty(); ++t) {
    if (m.tag_role(static_cast<int>(t)) != Role::Lesion) continue;
    UsLesion l;
    l.name = m.tag_names[t];
    Vec3 c = Vec3::Zero();
    for (int p = 0; p < m.particle_count(); ++p)
      if (m.particle_tags[p] >> t & 1u) { l.particles.push_back(p); c += m.rest_pos[p]; }
    if (l.particles.empty()) continue;
    c /= static_cast<double>(l.particles.size());
    for (int p : l.particles)
      l.radius = std::max(l.radius, (m.rest_pos[p] - c).norm() + 0.5 * m.components[m.component_of[p]].spacing);
    a.lesions.push_back(std::move(l));
  }
  a.component_index.assign(m.components.size(), -1);
  std::vector<double> volume;
  for (size_t c = 0; c < m.components.size() && a.components.size() < 32; ++c) {
    const Component& mc = m.components[c];
    if (mc.surface < 0 || m.surfaces[mc.surface].faces.empty()) continue;  // nothing to intersect
    UsComponent u;
    u.name = mc.name;
    u.tissue = tissue_for_component(mc);
    for (const auto& [name, t] : opt.tissue_overrides)
      if (name == mc.name) u.tissue = t;
    u.first_particle = mc.first_particle;
    u.particle_count = mc.particle_count;
    u.spacing = mc.spacing;
    u.faces = m.surfaces[mc.surface].faces;
    volume.push_back(enclosed_volume(m.rest_pos, u.faces));
    if ((u.tissue == Tissue::Bladder || u.tissue == Tissue::Bone) && opt.smooth_subdivisions > 0) {
      // smooth surface: the particle triangles subdivided at rest, carried by the component's particles
      std::vector<int> local(m.particle_count(), -1), carriers;
      std::vector<Vec3> v;
      std::vector<std::array<int, 3>> f;
      for (const auto& t : u.faces) {
        std::array<int, 3> g;
        for (int k = 0; k < 3; ++k) {
          if (local[t[k]] < 0) local[t[k]] = static_cast<int>(v.size()), v.push_back(m.rest_pos[t[k]]), carriers.push_back(t[k]);
          g[k] = local[t[k]];
        }
        f.push_back(g);
      }
      loop_subdivide(v, f, opt.smooth_subdivisions);
      const int base = add_carried(a, m.rest_pos, v, carriers);
      u.faces.clear();
      for (const auto& t : f) u.faces.push_back({base + t[0], base + t[1], base + t[2]});
    }
    a.component_index[c] = static_cast<int>(a.components.size());
    if (u.tissue == Tissue::Prostate && a.prostate < 0) a.prostate = static_cast<int>(a.components.size());
    a.components.push_back(std::move(u));
  }
  for (const anatomy::DisplayMesh& d : opt.display_meshes) {
    if (d.kind != anatomy::DisplayMesh::SeminalVesicle || a.components.size() >= 32 || d.mesh.faces.empty()) continue;
    UsComponent u;
    u.name = d.name;
    u.tissue = Tissue::SeminalVesicle;
    u.spacing = 0.0;
    const int base = static_cast<int>(m.rest_pos.size() + a.carried_particles.size());
    for (const auto& f : d.mesh.faces) u.faces.push_back({base + f[0], base + f[1], base + f[2]});
    a.carried_particles.insert(a.carried_particles.end(), d.carriers.begin(), d.carriers.end());
    a.carried_weights.insert(a.carried_weights.end(), d.weights.begin(), d.weights.end());
    a.carried_offsets.insert(a.carried_offsets.end(), d.offsets.begin(), d.offsets.end());
    volume.push_back(std::abs(signed_volume(d.mesh)));
    a.components.push_back(std::move(u));
  }
  std::vector<int> order(a.components.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return volume[i] < volume[j]; });
  for (size_t r = 0; r < order.size(); ++r) a.components[order[r]].priority = static_cast<int>(r);

  a.urethra = m.urethra;
  a.urethra_radius = opt.urethra_radius;
  a.calcifications = opt.calcifications;
  if (a.prostate >= 0) {
    // rest-space echo volume: Gaussian-weighted mean of the particles' echo (sigma = 0.3 h: close to
    // the nearest particle's value, with soft margins), so a lesion tagged on a few particles becomes
    // a blob of about their extent with an ill-defined margin, as on TRUS
    const UsComponent& pc = a.components[a.prostate];
    Vec3 lo = m.rest_pos[pc.first_particle], hi = lo;
    for (int p = pc.first_particle; p < pc.first_particle + pc.particle_count; ++p) {
      lo = lo.cwiseMin(m.rest_pos[p]);
      hi = hi.cwiseMax(m.rest_pos[p]);
    }
    const double margin = 2.0 * pc.spacing;
    RestVolume& v = a.prostate_echo;
    v.step = opt.voxel;
    v.origin = lo - Vec3::Constant(margin);
    v.nx = static_cast<int>(std::ceil((hi.x() - lo.x() + 2 * margin) / v.step)) + 1;
    v.ny = static_cast<int>(std::ceil((hi.y() - lo.y() + 2 * margin) / v.step)) + 1;
    v.nz = static_cast<int>(std::ceil((hi.z() - lo.z() + 2 * margin) / v.step)) + 1;
    const size_t nv = static_cast<size_t>(v.nx) * v.ny * v.nz;
    std::vector<double> num(nv, 0.0), den(nv, 0.0);
    const double sigma = 0.3 * pc.spacing, reach = 3.0 * sigma;
    for (int p = pc.first_particle; p < pc.first_particle + pc.particle_count; ++p) {
      const double e = prostate_particle_echo(m, p);
      const Vec3 q = (m.rest_pos[p] - v.origin) / v.step;
      const int r = static_cast<int>(std::ceil(reach / v.step));
      const int ci = static_cast<int>(std::lround(q.x())), cj = static_cast<int>(std::lround(q.y())),
                ck = static_cast<int>(std::lround(q.z()));
      for (int k = std::max(0, ck - r); k <= std::min(v.nz - 1, ck + r); ++k)
        for (int j = std::max(0, cj - r); j <= std::min(v.ny - 1, cj + r); ++j)
          for (int i = std::max(0, ci - r); i <= std::min(v.nx - 1, ci + r); ++i) {
            const double d2 = ((Vec3(i, j, k) - q) * v.step).squaredNorm();
            if (d2 > reach * reach) continue;
            const double w = std::exp(-0.5 * d2 / (sigma * sigma));
            const size_t idx = (static_cast<size_t>(k) * v.ny + j) * v.nx + i;
            num[idx] += w * e;
            den[idx] += w;
          }
    }
    v.value.assign(nv, 0.9f);
    for (size_t i = 0; i < nv; ++i)
      if (den[i] > 1e-9) v.value[i] = static_cast<float>(num[i] / den[i]);
    // urethra: the collapsed lumen hypoechoic (0.55: a subtle line through the receive aperture's
    // lateral blur, not a black band) with a thin bright (periurethral) rim, in rest space so it
    // deforms
    if (a.urethra.size() >= 2) {
      const double r = a.urethra_radius;
      for (int k = 0; k < v.nz; ++k)
        for (int j = 0; j < v.ny; ++j)
          for (int i = 0; i < v.nx; ++i) {
            const Vec3 p = v.origin + Vec3(i, j, k) * v.step;
            double d = 1e9;
            for (size_t s = 0; s + 1 < a.urethra.size(); ++s) d = std::min(d, segment_distance(p, a.urethra[s], a.urethra[s + 1]));
            float& val = v.value[(static_cast<size_t>(k) * v.ny + j) * v.nx + i];
            if (d < r) val = 0.55f;
            else if (d < r + 0.7e-3) val = std::max(val, 1.15f);
          }
    }
    // calcifications: bright foci (kCalcificationEcho and above: they also stop the beam)
    for (const auto& [c, rad] : opt.calcifications) {
      const Vec3 q = (c - v.origin) / v.step;
      const int reach = static_cast<int>(std::ceil(rad / v.step)) + 1;
      for (int k = std::max(0, static_cast<int>(q.z()) - reach); k <= std::min(v.nz - 1, static_cast<int>(q.z()) + reach); ++k)
        for (int j = std::max(0, static_cast<int>(q.y()) - reach); j <= std::min(v.ny - 1, static_cast<int>(q.y()) + reach); ++j)
          for (int i = std::max(0, static_cast<int>(q.x()) - reach); i <= std::min(v.nx - 1, static_cast<int>(q.x()) + reach); ++i) {
            const double d = (v.origin + Vec3(i, j, k) * v.step - c).norm();
            if (d <= rad + 0.5 * v.step) v.value[(static_cast<size_t>(k) * v.ny + j) * v.nx + i] = 8.0f * kCalcificationEcho;
          }
    }
  }
  return a;
}

std::vector<std::pair<Vec3, double>> read_calcifications_csv(const std::string& path, double unit_scale, const Vec3& translate) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "calcifications", "cannot open the file");
  std::vector<std::pair<Vec3, double>> out;
  std::string line;
  int ln = 0;
  bool header = true;
  while (std::getline(in, line)) {
    ++ln;
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    double x, y, z, r;
    if (!(ss >> x >> y >> z >> r) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(r)) {
      if (header) {  // header row (x_mm,y_mm,z_mm,radius_mm)
        header = false;
        continue;
      }
      throw InputError(path, ln, "calcifications", "expected four finite numbers x,y,z,radius");
    }
    header = false;
    if (!(r > 0.0) || r * unit_scale > 10e-3) throw InputError(path, ln, "calcifications", "radius must be in (0, 10] mm");
    out.emplace_back(Vec3(x, y, z) * unit_scale + translate, r * unit_scale);
  }
  return out;
}

}  // namespace ps::us
