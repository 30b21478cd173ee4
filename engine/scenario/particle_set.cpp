#include "engine/scenario/particle_set.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "engine/util/spatial_grid.h"

namespace ps {

namespace {

void add_edge(std::vector<std::vector<int>>& nb, int a, int b) {
  if (std::find(nb[a].begin(), nb[a].end(), b) == nb[a].end()) nb[a].push_back(b);
  if (std::find(nb[b].begin(), nb[b].end(), a) == nb[b].end()) nb[b].push_back(a);
}

}  // namespace

ParticleSet box_particles(const Vec3& min, const Vec3& max, double h, bool volumetric) {
  Eigen::Vector3i n;
  Vec3 step;
  for (int a = 0; a < 3; ++a) {
    n[a] = std::max(1, static_cast<int>(std::lround((max[a] - min[a]) / h)));
    step[a] = (max[a] - min[a]) / n[a];
  }
  const auto boundary = [&](int i, int j, int k) {
    return i == 0 || j == 0 || k == 0 || i == n[0] || j == n[1] || k == n[2];
  };
  // lattice index -> particle index (-1 when not a particle)
  std::vector<int> id((n[0] + 1) * (n[1] + 1) * (n[2] + 1), -1);
  const auto lat = [&](int i, int j, int k) { return (k * (n[1] + 1) + j) * (n[0] + 1) + i; };
  ParticleSet ps;
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        const bool b = boundary(i, j, k);
        if (!volumetric && !b) continue;
        id[lat(i, j, k)] = static_cast<int>(ps.pos.size());
        ps.pos.push_back(min + Vec3(i * step[0], j * step[1], k * step[2]));
        ps.on_surface.push_back(b ? 1 : 0);
      }
  ps.nbrs.resize(ps.pos.size());
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        const int p = id[lat(i, j, k)];
        if (p < 0) continue;
        const int c[3] = {i, j, k};
        for (int a = 0; a < 3; ++a)
          for (int s : {-1, 1}) {
            int d[3] = {c[0], c[1], c[2]};
            d[a] += s;
            if (d[a] < 0 || d[a] > n[a]) continue;
            const int q = id[lat(d[0], d[1], d[2])];
            if (q >= 0) ps.nbrs[p].push_back(q);
          }
      }
  // surface: each boundary face's lattice quads, two triangles each, outward
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const int ca = side ? n[a] : 0;
      for (int iu = 0; iu < n[u]; ++iu)
        for (int iv = 0; iv < n[v]; ++iv) {
          auto at = [&](int du, int dv) {
            int c[3];
            c[a] = ca;
            c[u] = iu + du;
            c[v] = iv + dv;
            return id[lat(c[0], c[1], c[2])];
          };
          const int p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          // e_u x e_v = e_a: (p00, p10, p11) faces +a; reversed on the min side
          if (side) {
            ps.faces.push_back({p00, p10, p11});
            ps.faces.push_back({p00, p11, p01});
          } else {
            ps.faces.push_back({p00, p11, p10});
            ps.faces.push_back({p00, p01, p11});
          }
        }
    }
  }
  return ps;
}

TriMesh cylinder_surface(const Vec3& base, const Vec3& axis_in, double radius, double length, double h) {
  const Vec3 ax = axis_in.normalized();
  const Vec3 u = (std::abs(ax.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(ax).normalized();
  const Vec3 v = ax.cross(u);
  const double two_pi = 2.0 * std::numbers::pi;
  const int ns = std::max(8, static_cast<int>(std::lround(two_pi * radius / h)));
  const int nz = std::max(1, static_cast<int>(std::lround(length / h)));
  const int nr = std::max(1, static_cast<int>(std::lround(radius / h)));
  TriMesh m;
  struct Ring { std::vector<int> idx; double offset; };
  auto make_ring = [&](double r, double z, int count, double offset) {
    Ring ring{{}, offset};
    for (int i = 0; i < count; ++i) {
      const double t = two_pi * (i + offset) / count;
      ring.idx.push_back(static_cast<int>(m.vertices.size()));
      m.vertices.push_back(base + z * ax + r * (std::cos(t) * u + std::sin(t) * v));
    }
    return ring;
  };
  // zip two closed loops ordered by angle into a strip of triangles
  auto zip = [&](const Ring& A, const Ring& B) {
    const int na = static_cast<int>(A.idx.size()), nb = static_cast<int>(B.idx.size());
    int i = 0, j = 0;
    while (i < na || j < nb) {
      const double ta = (i + 1 + A.offset) / na, tb = (j + 1 + B.offset) / nb;
      if (j >= nb || (i < na && ta <= tb)) {
        m.faces.push_back({A.idx[i % na], A.idx[(i + 1) % na], B.idx[j % nb]});
        ++i;
      } else {
        m.faces.push_back({A.idx[i % na], B.idx[(j + 1) % nb], B.idx[j % nb]});
        ++j;
      }
    }
  };
  std::vector<Ring> side;
  for (int k = 0; k <= nz; ++k) side.push_back(make_ring(radius, length * k / nz, ns, 0.0));
  for (int k = 0; k < nz; ++k) zip(side[k], side[k + 1]);
  for (int end = 0; end < 2; ++end) {
    const double z = end ? length : 0.0;
    Ring outer = side[end ? nz : 0];
    for (int r = nr - 1; r >= 1; --r) {
      const double rr = radius * r / nr;
      const int count = std::max(6, static_cast<int>(std::lround(two_pi * rr / h)));
      Ring inner = make_ring(rr, z, count, 0.5 * (r % 2));
      zip(inner, outer);
      outer = inner;
    }
    const int c = static_cast<int>(m.vertices.size());
    m.vertices.push_back(base + z * ax);
    const int no = static_cast<int>(outer.idx.size());
    for (int i = 0; i < no; ++i) m.faces.push_back({c, outer.idx[i], outer.idx[(i + 1) % no]});
  }
  // orient every face outward: caps along -/+axis, side radially
  for (auto& f : m.faces) {
    const Vec3 a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
    const Vec3 nrm = (b - a).cross(c - a);
    const Vec3 ctr = (a + b + c) / 3.0;
    const double z = (ctr - base).dot(ax);
    Vec3 out;
    const Vec3 radial = (ctr - base) - z * ax;
    if (z < 1e-9 * length && radial.norm() < radius * 0.999) out = -ax;
    else if (z > length * (1 - 1e-9) && radial.norm() < radius * 0.999) out = ax;
    else out = radial;
    if (nrm.dot(out) < 0) std::swap(f[1], f[2]);
  }
  return m;
}

ParticleSet surface_particles(const TriMesh& surface) {
  ParticleSet ps;
  ps.pos = surface.vertices;
  ps.on_surface.assign(ps.pos.size(), 1);
  ps.nbrs.resize(ps.pos.size());
  ps.faces = surface.faces;
  for (const auto& f : surface.faces)
    for (int e = 0; e < 3; ++e) add_edge(ps.nbrs, f[e], f[(e + 1) % 3]);
  for (auto& nb : ps.nbrs) std::sort(nb.begin(), nb.end());
  return ps;
}

ParticleSet volumetric_particles(const TriMesh& surface, double h, const std::function<bool(const Vec3&)>& inside,
                                 const std::function<double(const Vec3&)>& distance) {
  ParticleSet ps = surface_particles(surface);
  const int ns = static_cast<int>(ps.pos.size());
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& p : surface.vertices) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); }
  const Eigen::Vector3i n = ((hi - lo) / h).array().ceil().cast<int>();
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        const Vec3 p = lo + h * Vec3(i, j, k);
        if (inside(p) && distance(p) >= 0.45 * h) {
          ps.pos.push_back(p);
          ps.on_surface.push_back(0);
        }
      }
  ps.nbrs.resize(ps.pos.size());
  const SpatialGrid grid(ps.pos, h);
  // interior: nearest particle in each of the six axis cones
  for (int p = ns; p < static_cast<int>(ps.pos.size()); ++p) {
    int best[6];
    double bestd[6];
    std::fill(best, best + 6, -1);
    std::fill(bestd, bestd + 6, 1e300);
    grid.for_each_within(ps.pos[p], 1.75 * h, [&](int q, double d) {
      if (q == p || d <= 0.0) return;
      const Vec3 dir = ps.pos[q] - ps.pos[p];
      int a;
      dir.cwiseAbs().maxCoeff(&a);
      const int cone = 2 * a + (dir[a] < 0 ? 1 : 0);
      if (d < bestd[cone] || (d == bestd[cone] && q < best[cone])) { bestd[cone] = d; best[cone] = q; }
    });
    for (int c = 0; c < 6; ++c)
      if (best[c] >= 0) ps.nbrs[p].push_back(best[c]);
  }
  // surface particles: attach to the 2 nearest interior particles
  for (int p = 0; p < ns; ++p) {
    std::vector<std::pair<double, int>> cand;
    grid.for_each_within(ps.pos[p], 2.5 * h, [&](int q, double d) {
      if (q >= ns) cand.emplace_back(d, q);
    });
    std::sort(cand.begin(), cand.end());
    for (size_t c = 0; c < cand.size() && c < 2; ++c) ps.nbrs[p].push_back(cand[c].second);
  }
  return ps;
}

}  // namespace ps
