#include "engine/anatomy/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

namespace ps::anatomy {

TriMesh icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriMesh m;
  m.vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& v : m.vertices) v.normalize();
  m.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    // midpoint of each edge created once (keyed by the sorted vertex pair): conforming split
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const int id = static_cast<int>(m.vertices.size());
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      mid.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> faces;
    faces.reserve(4 * m.faces.size());
    for (const auto& f : m.faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      faces.push_back({f[0], ab, ca});
      faces.push_back({f[1], bc, ab});
      faces.push_back({f[2], ca, bc});
      faces.push_back({ab, bc, ca});
    }
    m.faces = std::move(faces);
  }
  // outward: on a sphere about the origin the face normal points along its centroid
  for (auto& f : m.faces) {
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
    if ((b - a).cross(c - a).dot(a + b + c) < 0.0) std::swap(f[1], f[2]);
  }
  return m;
}

TriMesh map_sphere(const TriMesh& unit_sphere, const std::function<Vec3(const Vec3&)>& map) {
  TriMesh m = unit_sphere;
  for (Vec3& v : m.vertices) v = map(v);
  return m;
}

TriMesh swept_tube(const std::vector<Vec3>& path, double radius, int ring, int cap_rings) {
  const int np = static_cast<int>(path.size());
  if (np < 2 || ring < 3 || cap_rings < 1 || !(radius > 0.0))
    throw std::invalid_argument("swept_tube: need >= 2 path points, >= 3 ring vertices, >= 1 cap ring, radius > 0");
  // tangents: mean of the adjacent segment directions
  std::vector<Vec3> T(np);
  for (int i = 0; i < np; ++i) {
    const Vec3 fwd = i + 1 < np ? (path[i + 1] - path[i]).normalized() : Vec3::Zero();
    const Vec3 back = i > 0 ? (path[i] - path[i - 1]).normalized() : Vec3::Zero();
    T[i] = (fwd + back).normalized();
  }
  // parallel transport of the normal: no twist about the path
  std::vector<Vec3> N(np), B(np);
  const Vec3 seed = std::abs(T[0].x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  N[0] = (seed - seed.dot(T[0]) * T[0]).normalized();
  for (int i = 1; i < np; ++i) N[i] = (N[i - 1] - N[i - 1].dot(T[i]) * T[i]).normalized();
  for (int i = 0; i < np; ++i) B[i] = T[i].cross(N[i]);

  TriMesh m;
  std::vector<std::vector<int>> rings;  // in order along the path, same angular order
  auto add_ring = [&](const Vec3& centre, const Vec3& n, const Vec3& b, double r) {
    std::vector<int> idx;
    for (int j = 0; j < ring; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / ring;
      idx.push_back(static_cast<int>(m.vertices.size()));
      m.vertices.push_back(centre + r * (std::cos(phi) * n + std::sin(phi) * b));
    }
    rings.push_back(std::move(idx));
  };
  const int start_pole = static_cast<int>(m.vertices.size());
  m.vertices.push_back(path[0] - radius * T[0]);
  for (int k = cap_rings - 1; k >= 1; --k) {
    const double th = 0.5 * std::numbers::pi * k / cap_rings;
    add_ring(path[0] - radius * std::sin(th) * T[0], N[0], B[0], radius * std::cos(th));
  }
  for (int i = 0; i < np; ++i) add_ring(path[i], N[i], B[i], radius);
  for (int k = 1; k < cap_rings; ++k) {
    const double th = 0.5 * std::numbers::pi * k / cap_rings;
    add_ring(path[np - 1] + radius * std::sin(th) * T[np - 1], N[np - 1], B[np - 1], radius * std::cos(th));
  }
  const int end_pole = static_cast<int>(m.vertices.size());
  m.vertices.push_back(path[np - 1] + radius * T[np - 1]);

  // faces: ring angle increases from N towards B = T x N, so (a, b, c) / (a, c, d) face outward
  // ((b - a) ~ B, (d - a) ~ T, B x T = N)
  const auto& first = rings.front();
  for (int j = 0; j < ring; ++j) m.faces.push_back({start_pole, first[(j + 1) % ring], first[j]});
  for (size_t k = 0; k + 1 < rings.size(); ++k)
    for (int j = 0; j < ring; ++j) {
      const int a = rings[k][j], b = rings[k][(j + 1) % ring], c = rings[k + 1][(j + 1) % ring], d = rings[k + 1][j];
      m.faces.push_back({a, b, c});
      m.faces.push_back({a, c, d});
    }
  const auto& last = rings.back();
  for (int j = 0; j < ring; ++j) m.faces.push_back({end_pole, last[j], last[(j + 1) % ring]});
  return m;
}

TriMesh grid_box(const Vec3& lo, const Vec3& hi, double edge) {
  Eigen::Vector3i n;
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, static_cast<int>(std::lround((hi[a] - lo[a]) / edge)));
  TriMesh m;
  std::map<std::array<int, 3>, int> id;  // lattice point on the boundary -> vertex
  auto vertex = [&](const std::array<int, 3>& c) {
    auto it = id.find(c);
    if (it != id.end()) return it->second;
    const int v = static_cast<int>(m.vertices.size());
    Vec3 p;
    for (int a = 0; a < 3; ++a) p[a] = c[a] == n[a] ? hi[a] : lo[a] + (hi[a] - lo[a]) * c[a] / n[a];
    m.vertices.push_back(p);
    id.emplace(c, v);
    return v;
  };
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    for (int side = 0; side < 2; ++side)
      for (int iu = 0; iu < n[u]; ++iu)
        for (int iv = 0; iv < n[v]; ++iv) {
          auto at = [&](int du, int dv) {
            std::array<int, 3> c{};
            c[a] = side ? n[a] : 0;
            c[u] = iu + du;
            c[v] = iv + dv;
            return vertex(c);
          };
          const int p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          // e_u x e_v = e_a: (p00, p10, p11) faces +a; reversed on the low side
          if (side) {
            m.faces.push_back({p00, p10, p11});
            m.faces.push_back({p00, p11, p01});
          } else {
            m.faces.push_back({p00, p11, p10});
            m.faces.push_back({p00, p01, p11});
          }
        }
  }
  return m;
}

std::vector<Vec3> resample_polyline(const std::vector<Vec3>& path, double step) {
  if (path.size() < 2) return path;
  std::vector<double> s(path.size(), 0.0);
  for (size_t i = 1; i < path.size(); ++i) s[i] = s[i - 1] + (path[i] - path[i - 1]).norm();
  const int n = std::max(1, static_cast<int>(std::lround(s.back() / step)));
  std::vector<Vec3> out;
  size_t seg = 0;
  for (int k = 0; k <= n; ++k) {
    const double t = s.back() * k / n;
    while (seg + 2 < path.size() && s[seg + 1] < t) ++seg;
    const double len = s[seg + 1] - s[seg];
    const double w = len > 0.0 ? std::clamp((t - s[seg]) / len, 0.0, 1.0) : 0.0;
    out.push_back(k == n ? path.back() : Vec3((1.0 - w) * path[seg] + w * path[seg + 1]));
  }
  return out;
}

}  // namespace ps::anatomy
