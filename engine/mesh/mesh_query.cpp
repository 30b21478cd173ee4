#include "engine/mesh/mesh_query.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ps {
namespace {

constexpr int kLeafSize = 4;
constexpr double kInf = std::numeric_limits<double>::infinity();

double box_dist2(const Vec3& p, const float* lo, const float* hi) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max(std::max(lo[k] - p[k], p[k] - hi[k]), 0.0);
    d2 += d * d;
  }
  return d2;
}

// Entry parameter of the ray into the box, or +inf when it misses within [0, t_max].
double ray_box(const Vec3& o, const Vec3& inv, const Vec3& dir, const float* lo, const float* hi,
               double t_max) {
  double t0 = 0.0, t1 = t_max;
  for (int k = 0; k < 3; ++k) {
    if (dir[k] == 0.0) {
      // Parallel to the slab: inside it or never (avoids 0 * inf = NaN).
      if (o[k] < lo[k] || o[k] > hi[k]) return kInf;
      continue;
    }
    double a = (double(lo[k]) - o[k]) * inv[k], b = (double(hi[k]) - o[k]) * inv[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return kInf;
  }
  return t0;
}

// Moeller-Trumbore; returns the ray parameter of the hit or +inf. Edges count as hits on both
// sides, so inside() votes over several directions instead of trusting one ray.
double ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (std::abs(det) <= 1e-14 * e1.norm() * e2.norm() * d.norm()) return kInf;   // parallel
  const double inv = 1.0 / det;
  const Vec3 tv = o - a;
  const double u = tv.dot(pv) * inv;
  if (u < 0.0 || u > 1.0) return kInf;
  const Vec3 qv = tv.cross(e1);
  const double v = d.dot(qv) * inv;
  if (v < 0.0 || u + v > 1.0) return kInf;
  return e2.dot(qv) * inv;
}

// Stores a double box as floats rounded outward, so the float box still contains it.
void store_box_floats(float* flo, float* fhi, const Vec3& lo, const Vec3& hi) {
  for (int k = 0; k < 3; ++k) {
    flo[k] = std::nextafter(static_cast<float>(lo[k]), -std::numeric_limits<float>::infinity());
    fhi[k] = std::nextafter(static_cast<float>(hi[k]), std::numeric_limits<float>::infinity());
  }
}

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;   // degenerate triangle: any vertex is as good
  const double v = vb / denom, w = vc / denom;
  return a + v * ab + w * ac;
}

}  // namespace

void MeshQuery::store_box(Node& n, int k, const Vec3& lo, const Vec3& hi) {
  store_box_floats(n.lo[k], n.hi[k], lo, hi);
}

MeshQuery::MeshQuery(const TriMesh& surface) {
  const size_t nv = surface.vertices.size();
  if (surface.faces.empty()) throw std::invalid_argument("MeshQuery: surface has no faces");
  for (size_t v = 0; v < nv; ++v)
    if (!surface.vertices[v].allFinite())
      throw std::invalid_argument("MeshQuery: vertex " + std::to_string(v) + " is not finite");
  tris_.reserve(surface.faces.size());
  for (size_t f = 0; f < surface.faces.size(); ++f) {
    const auto& t = surface.faces[f];
    for (int i : t)
      if (i < 0 || size_t(i) >= nv)
        throw std::invalid_argument("MeshQuery: face " + std::to_string(f) + " has a vertex index out of range");
    tris_.push_back({surface.vertices[t[0]], surface.vertices[t[1]], surface.vertices[t[2]], static_cast<int>(f)});
  }
  std::vector<Vec3> centroids(tris_.size());
  for (size_t i = 0; i < tris_.size(); ++i) centroids[i] = (tris_[i].a + tris_[i].b + tris_[i].c) / 3.0;
  nodes_.reserve(2 * tris_.size() / kLeafSize + 2);
  const Child root = build(0, static_cast<int>(tris_.size()), centroids);
  lo_ = root.lo;
  hi_ = root.hi;
  if (root.count > 0) {
    // Few triangles: wrap the single leaf in a root node so traversal always starts at a node.
    Node n{};
    store_box(n, 0, root.lo, root.hi);
    n.index[0] = root.index;
    n.count[0] = root.count;
    n.count[1] = -1;
    nodes_.push_back(n);
  }
  planes_.resize(tris_.size());
  for (size_t i = 0; i < tris_.size(); ++i) {
    const Tri& t = tris_[i];
    const Vec3 n = (t.b - t.a).cross(t.c - t.a);
    const double len = n.norm();
    planes_[i].n = len > 0 ? Vec3(n / len) : Vec3::Zero();
    planes_[i].d = planes_[i].n.dot(t.a);
  }
}

// Builds the subtree for tris_[first, first + count): a leaf when small, else a node split at
// the median centroid along the longest centroid axis. Balanced, so the depth stays at
// ~log2(n / kLeafSize) and fixed-size traversal stacks suffice. The root node, when there is
// one, is built first and so is nodes_[0].
MeshQuery::Child MeshQuery::build(int first, int count, std::vector<Vec3>& centroids) {
  Child c{first, count, Vec3::Constant(kInf), Vec3::Constant(-kInf)};
  Vec3 clo = c.lo, chi = c.hi;
  for (int i = first; i < first + count; ++i) {
    const Tri& t = tris_[i];
    c.lo = c.lo.cwiseMin(t.a).cwiseMin(t.b).cwiseMin(t.c);
    c.hi = c.hi.cwiseMax(t.a).cwiseMax(t.b).cwiseMax(t.c);
    clo = clo.cwiseMin(centroids[i]);
    chi = chi.cwiseMax(centroids[i]);
  }
  if (count <= kLeafSize) return c;
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int half = count / 2;
  // Partition a permutation so that triangles and centroids move together.
  std::vector<int> perm(count);
  for (int i = 0; i < count; ++i) perm[i] = first + i;
  std::nth_element(perm.begin(), perm.begin() + half, perm.end(),
                   [&](int x, int y) { return centroids[x][axis] < centroids[y][axis]; });
  std::vector<Tri> tmp_t(count);
  std::vector<Vec3> tmp_c(count);
  for (int i = 0; i < count; ++i) {
    tmp_t[i] = tris_[perm[i]];
    tmp_c[i] = centroids[perm[i]];
  }
  std::copy(tmp_t.begin(), tmp_t.end(), tris_.begin() + first);
  std::copy(tmp_c.begin(), tmp_c.end(), centroids.begin() + first);

  const int ni = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  const Child kids[2] = {build(first, half, centroids), build(first + half, count - half, centroids)};
  Node& n = nodes_[ni];   // only after the recursion: it may have reallocated nodes_
  for (int k = 0; k < 2; ++k) {
    store_box(n, k, kids[k].lo, kids[k].hi);
    n.index[k] = kids[k].index;
    n.count[k] = kids[k].count;
  }
  c.index = ni;
  c.count = 0;
  return c;
}

MeshQuery::Closest MeshQuery::closest(const Vec3& p) const {
  Closest best{Vec3::Zero(), kInf, -1};
  double best_d2 = kInf;
  // Entries carry the box distance computed when their parent ordered them.
  struct Entry {
    int index, count;
    double d2;
  } stack[128];
  int top = 0;
  stack[top++] = {0, 0, 0.0};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best_d2) continue;
    if (e.count > 0) {
      for (int i = e.index; i < e.index + e.count; ++i) {
        // The distance to the plane bounds the distance to the triangle from below at the
        // cost of one dot product: it skips most triangles where many boxes are nearly
        // equidistant (deep inside a round organ).
        const Plane& pl = planes_[i];
        const double h = pl.n.dot(p) - pl.d;
        if (h * h >= best_d2) continue;
        const Tri& t = tris_[i];
        const Vec3 q = closest_on_triangle(p, t.a, t.b, t.c);
        const double d2 = (q - p).squaredNorm();
        if (d2 < best_d2) {
          best_d2 = d2;
          best.point = q;
          best.face = t.face;
        }
      }
      continue;
    }
    const Node& n = nodes_[e.index];
    double d[2];
    for (int k = 0; k < 2; ++k) d[k] = n.count[k] < 0 ? kInf : box_dist2(p, n.lo[k], n.hi[k]);
    // Push the farther child first so the nearer one is searched first and prunes more.
    const int near = d[1] < d[0] ? 1 : 0, far = 1 - near;
    if (d[far] < best_d2) stack[top++] = {n.index[far], n.count[far], d[far]};
    if (d[near] < best_d2) stack[top++] = {n.index[near], n.count[near], d[near]};
  }
  best.distance = std::sqrt(best_d2);
  return best;
}

int MeshQuery::crossings(const Vec3& p, const Vec3& dir) const {
  const Vec3 inv = dir.cwiseInverse();
  int hits = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    for (int k = 0; k < 2; ++k) {
      if (n.count[k] < 0 || ray_box(p, inv, dir, n.lo[k], n.hi[k], kInf) == kInf) continue;
      if (n.count[k] == 0) {
        stack[top++] = n.index[k];
        continue;
      }
      for (int i = n.index[k]; i < n.index[k] + n.count[k]; ++i) {
        const Tri& t = tris_[i];
        const double s = ray_triangle(p, dir, t.a, t.b, t.c);
        if (s > 0.0 && s < kInf) ++hits;
      }
    }
  }
  return hits;
}

bool MeshQuery::inside(const Vec3& p) const {
  if (!((p.array() >= lo_.array()).all() && (p.array() <= hi_.array()).all())) return false;
  // Skew directions: no axis, face diagonal or body diagonal, so grid-aligned meshes (boxes,
  // voxel-clustered surfaces) do not put edges exactly in the ray's path.
  static const Vec3 kDirs[3] = {Vec3(0.5377, 0.6948, 0.4771).normalized(),
                                Vec3(-0.7291, 0.3137, 0.6083).normalized(),
                                Vec3(0.2213, -0.8419, 0.4923).normalized()};
  const bool a = crossings(p, kDirs[0]) % 2 == 1;
  const bool b = crossings(p, kDirs[1]) % 2 == 1;
  if (a == b) return a;
  return crossings(p, kDirs[2]) % 2 == 1;
}

double MeshQuery::signed_distance(const Vec3& p) const {
  const double d = distance(p);
  return inside(p) ? -d : d;
}

std::optional<double> MeshQuery::ray_hit(const Vec3& origin, const Vec3& dir) const {
  const double len = dir.norm();
  if (!(len > 0.0) || !std::isfinite(len) || !origin.allFinite()) return std::nullopt;
  const Vec3 d = dir / len;
  const Vec3 inv = d.cwiseInverse();
  double best = kInf;
  struct Entry {
    int index, count;
    double t;
  } stack[128];
  int top = 0;
  stack[top++] = {0, 0, 0.0};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.t > best) continue;
    if (e.count > 0) {
      for (int i = e.index; i < e.index + e.count; ++i) {
        const Tri& t = tris_[i];
        const double s = ray_triangle(origin, d, t.a, t.b, t.c);
        if (s >= 0.0 && s < best) best = s;
      }
      continue;
    }
    const Node& n = nodes_[e.index];
    double t[2];
    for (int k = 0; k < 2; ++k) t[k] = n.count[k] < 0 ? kInf : ray_box(origin, inv, d, n.lo[k], n.hi[k], best);
    const int near = t[1] < t[0] ? 1 : 0, far = 1 - near;
    if (t[far] < kInf) stack[top++] = {n.index[far], n.count[far], t[far]};
    if (t[near] < kInf) stack[top++] = {n.index[near], n.count[near], t[near]};
  }
  if (best == kInf) return std::nullopt;
  return best;
}

}  // namespace ps
