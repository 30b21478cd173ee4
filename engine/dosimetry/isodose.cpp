#include "engine/dosimetry/isodose.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace ps::dosimetry {

double DoseField::at(const Vec3& p) const {
  const GridSpec& g = spec;
  if (dose_gy.size() != g.size() || g.nx < 2 || g.ny < 2 || g.nz < 2) return 0.0;
  const Vec3 q = (p - g.origin_mm) / g.spacing_mm;
  if (!(q.x() >= 0 && q.y() >= 0 && q.z() >= 0 && q.x() <= g.nx - 1 && q.y() <= g.ny - 1 && q.z() <= g.nz - 1)) return 0.0;
  const int i = std::min(static_cast<int>(q.x()), g.nx - 2), j = std::min(static_cast<int>(q.y()), g.ny - 2),
            k = std::min(static_cast<int>(q.z()), g.nz - 2);
  const double u = q.x() - i, v = q.y() - j, w = q.z() - k;
  auto d = [&](int a, int b, int c) { return static_cast<double>(dose_gy[g.index(i + a, j + b, k + c)]); };
  const double c00 = d(0, 0, 0) * (1 - u) + d(1, 0, 0) * u, c10 = d(0, 1, 0) * (1 - u) + d(1, 1, 0) * u;
  const double c01 = d(0, 0, 1) * (1 - u) + d(1, 0, 1) * u, c11 = d(0, 1, 1) * (1 - u) + d(1, 1, 1) * u;
  return (c00 * (1 - v) + c10 * v) * (1 - w) + (c01 * (1 - v) + c11 * v) * w;
}

void plane_isodose(const DoseField& f, const PixelPlane& pl, const std::vector<double>& levels, int step_px,
                   std::vector<IsoSegment>& out) {
  out.clear();
  if (pl.width < 2 || pl.height < 2 || levels.empty()) return;
  const int step = std::max(1, step_px);
  // raster nodes at multiples of step, the last row and column on the image's edge
  std::vector<float> xs, ys;
  for (int x = 0; x < pl.width - 1; x += step) xs.push_back(static_cast<float>(x));
  xs.push_back(static_cast<float>(pl.width - 1));
  for (int y = 0; y < pl.height - 1; y += step) ys.push_back(static_cast<float>(y));
  ys.push_back(static_cast<float>(pl.height - 1));
  const size_t nw = xs.size(), nh = ys.size();
  std::vector<float> v(nw * nh);
  for (size_t j = 0; j < nh; ++j)
    for (size_t i = 0; i < nw; ++i)
      v[j * nw + i] = static_cast<float>(f.at(pl.p00_mm + xs[i] * pl.dcol_mm + ys[j] * pl.drow_mm));
  for (size_t L = 0; L < levels.size(); ++L) {
    const float lv = static_cast<float>(levels[L]);
    for (size_t j = 0; j + 1 < nh; ++j)
      for (size_t i = 0; i + 1 < nw; ++i) {
        // corners counter-clockwise in the raster: (i,j), (i+1,j), (i+1,j+1), (i,j+1)
        const float c[4] = {v[j * nw + i], v[j * nw + i + 1], v[(j + 1) * nw + i + 1], v[(j + 1) * nw + i]};
        const float px[4] = {xs[i], xs[i + 1], xs[i + 1], xs[i]};
        const float py[4] = {ys[j], ys[j], ys[j + 1], ys[j + 1]};
        int in = 0;
        for (int k = 0; k < 4; ++k) in |= (c[k] >= lv) << k;
        if (in == 0 || in == 15) continue;
        // crossing on edge e (corner e to corner e+1)
        float ex[4], ey[4];
        bool cut[4];
        for (int e = 0; e < 4; ++e) {
          const int a = e, b = (e + 1) & 3;
          cut[e] = ((in >> a) & 1) != ((in >> b) & 1);
          if (!cut[e]) continue;
          const float t = (lv - c[a]) / (c[b] - c[a]);
          ex[e] = px[a] + t * (px[b] - px[a]);
          ey[e] = py[a] + t * (py[b] - py[a]);
        }
        auto seg = [&](int e0, int e1) { out.push_back({ex[e0], ey[e0], ex[e1], ey[e1], static_cast<uint8_t>(L)}); };
        if (in == 5 || in == 10) {  // saddle: the cell's mean says whether corners 0 and 2 connect
          const bool centre_in = 0.25f * (c[0] + c[1] + c[2] + c[3]) >= lv;
          if (centre_in == static_cast<bool>(in & 1)) {
            seg(0, 1);
            seg(2, 3);
          } else {
            seg(3, 0);
            seg(1, 2);
          }
          continue;
        }
        int e0 = -1, e1 = -1;
        for (int e = 0; e < 4; ++e)
          if (cut[e]) (e0 < 0 ? e0 : e1) = e;
        seg(e0, e1);
      }
  }
}

IsoSurface isodose_surface(const DoseField& f, double level, int stride) {
  IsoSurface s;
  const GridSpec& g = f.spec;
  const int st = std::max(1, stride);
  if (f.dose_gy.size() != g.size()) return s;
  const int nx = (g.nx - 1) / st + 1, ny = (g.ny - 1) / st + 1, nz = (g.nz - 1) / st + 1;  // nodes taken
  if (nx < 2 || ny < 2 || nz < 2) return s;
  auto node = [&](int i, int j, int k) { return (static_cast<size_t>(k) * ny + j) * nx + i; };
  auto val = [&](int i, int j, int k) { return f.dose_gy[g.index(i * st, j * st, k * st)]; };
  auto pos = [&](int i, int j, int k) { return g.centre_mm(i * st, j * st, k * st); };
  auto grad = [&](int i, int j, int k) {  // central differences [Gy/mm], one-sided on the edges
    const double h = g.spacing_mm * st;
    auto diff = [&](int a, int n, auto at) {
      const int lo = std::max(0, a - 1), hi = std::min(n - 1, a + 1);
      return (at(hi) - at(lo)) / (h * std::max(1, hi - lo));
    };
    const double gx = diff(i, nx, [&](int a) { return static_cast<double>(val(a, j, k)); });
    const double gy = diff(j, ny, [&](int a) { return static_cast<double>(val(i, a, k)); });
    const double gz = diff(k, nz, [&](int a) { return static_cast<double>(val(i, j, a)); });
    return Vec3(gx, gy, gz);
  };
  // six tetrahedra around the diagonal 0-7 of a cell (corner bits: 1 x, 2 y, 4 z)
  static constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  std::unordered_map<uint64_t, int> on_edge;
  const float lv = static_cast<float>(level);
  auto vertex = [&](const int (&a)[3], const int (&b)[3]) {
    size_t na = node(a[0], a[1], a[2]), nb = node(b[0], b[1], b[2]);
    const bool swap = na > nb;
    if (swap) std::swap(na, nb);
    const uint64_t key = static_cast<uint64_t>(na) * (static_cast<uint64_t>(nx) * ny * nz) + nb;
    const auto it = on_edge.find(key);
    if (it != on_edge.end()) return it->second;
    const double va = val(a[0], a[1], a[2]), vb = val(b[0], b[1], b[2]);
    const double t = std::clamp((level - va) / (vb - va), 0.0, 1.0);
    const Vec3 p = (1 - t) * pos(a[0], a[1], a[2]) + t * pos(b[0], b[1], b[2]);
    Vec3 n = -((1 - t) * grad(a[0], a[1], a[2]) + t * grad(b[0], b[1], b[2]));
    n = n.norm() > 1e-12 ? n.normalized() : Vec3::UnitZ();
    const int id = static_cast<int>(s.vertices_mm.size());
    s.vertices_mm.push_back(p);
    s.normals.push_back(n);
    on_edge.emplace(key, id);
    return id;
  };
  auto triangle = [&](int a, int b, int c) {
    if (a == b || b == c || a == c) return;
    const Vec3 n = (s.vertices_mm[b] - s.vertices_mm[a]).cross(s.vertices_mm[c] - s.vertices_mm[a]);
    const Vec3 out = s.normals[a] + s.normals[b] + s.normals[c];
    if (n.dot(out) < 0) std::swap(b, c);
    s.faces.push_back({a, b, c});
  };
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        int cn[8][3];
        float cv[8];
        int in = 0;
        for (int c = 0; c < 8; ++c) {
          cn[c][0] = i + (c & 1);
          cn[c][1] = j + ((c >> 1) & 1);
          cn[c][2] = k + ((c >> 2) & 1);
          cv[c] = val(cn[c][0], cn[c][1], cn[c][2]);
          in += cv[c] >= lv;
        }
        if (in == 0 || in == 8) continue;
        for (const auto& t : kTets) {
          int ins[4], outs[4], ni = 0, no = 0;
          for (int q = 0; q < 4; ++q) (cv[t[q]] >= lv ? ins[ni++] : outs[no++]) = t[q];
          if (ni == 0 || no == 0) continue;
          if (ni == 1 || no == 1) {
            const int lone = ni == 1 ? ins[0] : outs[0];
            const int* other = ni == 1 ? outs : ins;
            triangle(vertex(cn[lone], cn[other[0]]), vertex(cn[lone], cn[other[1]]), vertex(cn[lone], cn[other[2]]));
          } else {  // two and two: a quad
            const int a = vertex(cn[ins[0]], cn[outs[0]]), b = vertex(cn[ins[0]], cn[outs[1]]);
            const int c = vertex(cn[ins[1]], cn[outs[1]]), d = vertex(cn[ins[1]], cn[outs[0]]);
            triangle(a, b, c);
            triangle(a, c, d);
          }
        }
      }
  return s;
}

}  // namespace ps::dosimetry
