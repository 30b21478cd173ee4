#include "engine/mesh/mesh_simplify.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "engine/mesh/edge_collapse.h"
#include "engine/mesh/mesh_check.h"
#include "engine/mesh/mesh_query.h"

namespace ps {
namespace {

// Grid cell per requested spacing: calibrated so the mean edge of the result is about the
// spacing (edges join neighbouring cells, often diagonally).
constexpr double kRemeshCellPerSpacing = 1.0;
constexpr int kRelaxIterations = 4;

uint64_t edge_key(int a, int b) {
  return (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
}

struct CellHash {
  size_t operator()(const std::array<int64_t, 3>& c) const {
    uint64_t h = 1469598103934665603ull;
    for (int64_t x : c) h = (h ^ uint64_t(x)) * 1099511628211ull;
    return static_cast<size_t>(h ^ (h >> 31));
  }
};

// Clustering output as a 2-chain: faces over the same three vertices add up with their
// orientation signs, so an opposite pair cancels (two sheets of the surface that met in one
// cell layer) and a surplus keeps one face per unit. Collapsed faces (repeated vertex) go too.
// The sum keeps every edge's forward and backward uses equal, so no boundary edge can appear;
// check_mesh catches what remains non-manifold.
void cancel_faces(TriMesh& m) {
  struct Key {
    std::array<int, 3> s;
    int sign, idx;
  };
  std::vector<Key> keys;
  keys.reserve(m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f) {
    auto t = m.faces[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    const int sign = t[1] < t[2] ? 1 : -1;
    if (sign < 0) std::swap(t[1], t[2]);
    keys.push_back({t, sign, static_cast<int>(f)});
  }
  std::sort(keys.begin(), keys.end(),
            [](const Key& a, const Key& b) { return a.s != b.s ? a.s < b.s : a.idx < b.idx; });
  std::vector<std::array<int, 3>> faces;
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    int net = 0;
    while (j < keys.size() && keys[j].s == keys[i].s) net += keys[j++].sign;
    for (int k = 0; k < std::abs(net); ++k) {
      auto t = keys[i].s;
      if (net < 0) std::swap(t[1], t[2]);
      faces.push_back(t);
    }
    i = j;
  }
  m.faces = std::move(faces);
}

void drop_unreferenced(TriMesh& m) {
  std::vector<int> id(m.vertices.size(), -1);
  for (const auto& t : m.faces)
    for (int i : t) id[i] = 0;
  std::vector<Vec3> v;
  for (size_t i = 0; i < m.vertices.size(); ++i)
    if (id[i] == 0) {
      id[i] = static_cast<int>(v.size());
      v.push_back(m.vertices[i]);
    }
  for (auto& t : m.faces)
    for (int& i : t) i = id[i];
  m.vertices = std::move(v);
}

// Total genus of a closed surface: components - Euler characteristic / 2, E = 3F/2.
int genus(const MeshReport& r) {
  const int referenced = r.vertices - r.unreferenced_vertices;
  return r.components - (referenced - r.faces / 2) / 2;
}

double mean_edge(const TriMesh& m) {
  double sum = 0.0;
  for (const auto& t : m.faces)
    for (int k = 0; k < 3; ++k) sum += (m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm();
  return m.faces.empty() ? 0.0 : sum / (3.0 * m.faces.size());
}

// One clustering of `fine` on a grid of `cell` [m] shifted by `offset` cells.
TriMesh cluster(const TriMesh& fine, const Vec3& origin, double cell, double offset) {
  const size_t nv = fine.vertices.size();
  std::unordered_map<std::array<int64_t, 3>, int, CellHash> cell_id;
  cell_id.reserve(nv / 2 + 1);
  std::vector<int> cid(nv);
  for (size_t v = 0; v < nv; ++v) {
    const Vec3 q = (fine.vertices[v] - origin) / cell + Vec3::Constant(offset);
    const std::array<int64_t, 3> c{int64_t(std::floor(q.x())), int64_t(std::floor(q.y())), int64_t(std::floor(q.z()))};
    cid[v] = cell_id.try_emplace(c, static_cast<int>(cell_id.size())).first->second;
  }
  const size_t nc = cell_id.size();
  // Per cell: plane quadric (A, b) of the faces around its vertices, and the vertex mean.
  std::vector<Eigen::Matrix3d> A(nc, Eigen::Matrix3d::Zero());
  std::vector<Vec3> b(nc, Vec3::Zero()), mean(nc, Vec3::Zero());
  std::vector<int> count(nc, 0);
  for (size_t v = 0; v < nv; ++v) {
    mean[cid[v]] += fine.vertices[v];
    ++count[cid[v]];
  }
  for (size_t c = 0; c < nc; ++c) mean[c] /= count[c];
  for (const auto& t : fine.faces) {
    const Vec3& p = fine.vertices[t[0]];
    const Vec3 n2 = (fine.vertices[t[1]] - p).cross(fine.vertices[t[2]] - p);
    const double len = n2.norm();
    if (!(len > 0)) continue;
    const Vec3 n = n2 / len;
    const double w = 0.5 * len;   // area weight
    const Eigen::Matrix3d nn = w * n * n.transpose();
    const Vec3 nd = w * n * n.dot(p);
    for (int k = 0; k < 3; ++k) {
      A[cid[t[k]]] += nn;
      b[cid[t[k]]] += nd;
    }
  }
  TriMesh out;
  out.vertices.resize(nc);
  for (size_t c = 0; c < nc; ++c) {
    // Minimise x^T A x - 2 b^T x around the mean, ignoring directions the planes leave free
    // (flat patch: tangential; crease: along it) so that the vertex stays put there.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A[c]);
    const Vec3 r = b[c] - A[c] * mean[c];
    const double lmax = es.eigenvalues().cwiseAbs().maxCoeff();
    Vec3 x = mean[c];
    for (int k = 0; k < 3; ++k) {
      const double l = es.eigenvalues()[k];
      if (l > 1e-3 * lmax && l > 0) x += es.eigenvectors().col(k) * (es.eigenvectors().col(k).dot(r) / l);
    }
    // A far-off optimum means nearly parallel planes from opposite sides: keep the mean.
    out.vertices[c] = ((x - mean[c]).norm() <= cell && x.allFinite()) ? x : mean[c];
  }
  out.faces.reserve(fine.faces.size());
  for (const auto& t : fine.faces) out.faces.push_back({cid[t[0]], cid[t[1]], cid[t[2]]});
  cancel_faces(out);
  drop_unreferenced(out);
  return out;
}

// Tangential Laplacian relaxation with projection back onto the input surface: evens out the
// edge lengths clustering leaves (cells cut the surface at arbitrary places) and unfolds the
// occasional face that QEM placement turned over, without changing topology.
void relax_on_surface(TriMesh& m, const MeshQuery& q, int iterations) {
  const size_t nv = m.vertices.size();
  std::vector<std::vector<int>> nbr(nv);
  for (const auto& t : m.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      nbr[a].push_back(b);   // each edge appears once per direction on a closed surface
    }
  std::vector<Vec3> normal(nv), next(nv);
  for (int it = 0; it < iterations; ++it) {
    std::fill(normal.begin(), normal.end(), Vec3::Zero());
    for (const auto& t : m.faces) {
      const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
      for (int i : t) normal[i] += n;   // area-weighted
    }
    for (size_t v = 0; v < nv; ++v) {
      Vec3 c = Vec3::Zero();
      for (int w : nbr[v]) c += m.vertices[w];
      c /= static_cast<double>(nbr[v].size());
      const Vec3 n = normal[v].normalized();
      Vec3 u = c - m.vertices[v];
      if (n.allFinite()) u -= u.dot(n) * n;
      next[v] = q.closest_point(m.vertices[v] + 0.5 * u);
    }
    m.vertices.swap(next);
  }
}

// A polyhedron with its vertices on a convex surface is smaller than the surface (chords cut
// the curvature; ~3 % at 3 mm on a 20 mm body). Offsetting all vertices along their normals by
// the volume deficit over the area restores the volume; two rounds absorb the linearisation.
// The offset is a small fraction of the edge length, so it cannot fold faces.
void restore_volume(TriMesh& m, double target_volume) {
  std::vector<Vec3> normal(m.vertices.size());
  for (int round = 0; round < 2; ++round) {
    std::fill(normal.begin(), normal.end(), Vec3::Zero());
    double area = 0.0;
    for (const auto& t : m.faces) {
      const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
      area += 0.5 * n.norm();
      for (int i : t) normal[i] += n;
    }
    const double offset = (target_volume - signed_volume(m)) / area;   // [m]
    if (!std::isfinite(offset)) return;
    for (size_t v = 0; v < m.vertices.size(); ++v) {
      const Vec3 n = normal[v].normalized();
      if (n.allFinite()) m.vertices[v] += offset * n;
    }
  }
}

// Faces whose normal points against the input surface near them: clustering folded the
// surface over (valid topology, wrong geometry).
int folded_faces(const TriMesh& m, const TriMesh& input, const MeshQuery& q) {
  int folded = 0;
  for (const auto& t : m.faces) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const auto& f = input.faces[q.closest((a + b + c) / 3.0).face];
    const Vec3& p = input.vertices[f[0]];
    const Vec3 ni = (input.vertices[f[1]] - p).cross(input.vertices[f[2]] - p);
    if (n.dot(ni) <= 0) ++folded;
  }
  return folded;
}

}  // namespace

TriMesh subdivide_to_spacing(const TriMesh& mesh, double max_edge) {
  if (!(max_edge > 0) || !std::isfinite(max_edge))
    throw std::invalid_argument("subdivide_to_spacing: edge length must be positive and finite");
  // An equilateral triangle is the largest one with edges <= max_edge: refuse early when even
  // those would not fit the face limit, instead of allocating pass after pass.
  double area = 0.0;
  for (const auto& t : mesh.faces)
    area += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
  if (area / (0.25 * std::sqrt(3.0) * max_edge * max_edge) > static_cast<double>(kMaxSubdivideFaces))
    throw std::invalid_argument("subdivide_to_spacing: more than " + std::to_string(kMaxSubdivideFaces) +
                                " faces at edge length " + std::to_string(max_edge) + " m");
  TriMesh m = mesh;
  const double max2 = max_edge * max_edge;
  // Each pass at least halves every marked edge and the new medians are shorter than the
  // face's other sides, so a few dozen passes cover any ratio a double can express.
  for (int pass = 0; pass < 64; ++pass) {
    std::unordered_map<uint64_t, int> mid;
    for (const auto& t : m.faces)
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        if ((m.vertices[a] - m.vertices[b]).squaredNorm() > max2 && !mid.count(edge_key(a, b))) {
          mid[edge_key(a, b)] = static_cast<int>(m.vertices.size());
          m.vertices.push_back(0.5 * (m.vertices[a] + m.vertices[b]));
        }
      }
    if (mid.empty()) break;
    std::vector<std::array<int, 3>> faces;
    faces.reserve(m.faces.size() * 2);
    for (auto t : m.faces) {
      std::array<int, 3> mp;
      int marked = 0;
      for (int k = 0; k < 3; ++k) {
        auto it = mid.find(edge_key(t[k], t[(k + 1) % 3]));
        mp[k] = it == mid.end() ? -1 : it->second;
        marked += mp[k] >= 0;
      }
      if (marked == 0) {
        faces.push_back(t);
      } else if (marked == 3) {
        faces.push_back({t[0], mp[0], mp[2]});
        faces.push_back({mp[0], t[1], mp[1]});
        faces.push_back({mp[2], mp[1], t[2]});
        faces.push_back({mp[0], mp[1], mp[2]});
      } else {
        // Rotate so that the marked edges are 0 (v0-v1) and, for two, 1 (v1-v2).
        int r = 0;
        if (marked == 1) r = mp[0] >= 0 ? 0 : mp[1] >= 0 ? 1 : 2;
        else r = mp[2] < 0 ? 0 : mp[0] < 0 ? 1 : 2;
        std::rotate(t.begin(), t.begin() + r, t.end());
        std::rotate(mp.begin(), mp.begin() + r, mp.end());
        if (marked == 1) {
          faces.push_back({t[0], mp[0], t[2]});
          faces.push_back({mp[0], t[1], t[2]});
        } else {
          faces.push_back({mp[0], t[1], mp[1]});
          // Split the remaining quad v0, m01, m12, v2 along its shorter diagonal.
          const auto& V = m.vertices;
          if ((V[t[0]] - V[mp[1]]).squaredNorm() <= (V[mp[0]] - V[t[2]]).squaredNorm()) {
            faces.push_back({t[0], mp[0], mp[1]});
            faces.push_back({t[0], mp[1], t[2]});
          } else {
            faces.push_back({t[0], mp[0], t[2]});
            faces.push_back({mp[0], mp[1], t[2]});
          }
        }
      }
    }
    if (static_cast<long long>(faces.size()) > kMaxSubdivideFaces)
      throw std::invalid_argument("subdivide_to_spacing: more than " + std::to_string(kMaxSubdivideFaces) +
                                  " faces at edge length " + std::to_string(max_edge) + " m");
    m.faces = std::move(faces);
  }
  return m;
}

TriMesh remesh_to_spacing(const TriMesh& input, double spacing, RemeshStats* stats) {
  if (!(spacing > 0) || !std::isfinite(spacing))
    throw std::invalid_argument("remesh_to_spacing: spacing must be positive and finite");
  const MeshReport in_report = check_mesh(input);
  if (!in_report.valid_solid())
    throw std::invalid_argument("remesh_to_spacing: input is not a valid closed surface: " + in_report.summary());

  // Fine enough that every grid cell the surface passes through holds a vertex.
  const TriMesh fine = subdivide_to_spacing(input, 0.5 * spacing * kRemeshCellPerSpacing);
  Vec3 lo = fine.vertices[0];
  for (const Vec3& v : fine.vertices) lo = lo.cwiseMin(v);
  const MeshQuery query(input);
  const double input_volume = signed_volume(input);

  RemeshStats st;
  static const double kScales[] = {1.0, 0.9, 0.8, 0.7, 0.6, 0.5};
  static const double kOffsets[] = {0.0, 0.5, 0.25};
  for (double s : kScales)
    for (double off : kOffsets) {
      const double cell = spacing * kRemeshCellPerSpacing * s;
      ++st.attempts;
      TriMesh out = cluster(fine, lo, cell, off);
      if (out.faces.size() < 4) continue;
      const MeshReport r = check_mesh(out);
      // Same total genus: clustering must not close a hole through the body or open a handle.
      if (!r.valid_solid() || genus(r) != genus(in_report)) continue;
      relax_on_surface(out, query, kRelaxIterations);
      restore_volume(out, input_volume);
      if (!check_mesh(out).valid_solid() || folded_faces(out, input, query) > 0) continue;
      st.cell_m = cell;
      st.mean_edge_m = mean_edge(out);
      if (stats) *stats = st;
      return out;
    }
  // Every clustering broke the topology (features thinner than half the spacing): coarsen by
  // local edge collapses instead, which keep the topology whatever the wall thickness.
  TriMesh out = subdivide_to_spacing(input, spacing);
  const double input_edge = mean_edge(out);
  for (double min_edge = kCollapseEdgePerSpacing * spacing; min_edge > 0.5 * input_edge; min_edge *= 0.85) {
    // coarsest first; a collapse that folds against the input (the simplified surface cutting
    // through a wall thinner than its edges) is retried with shorter edges, until there would be
    // hardly anything left to collapse
    TriMesh col = collapse_short_edges(out, min_edge);
    const MeshReport cr = check_mesh(col);
    if (!cr.valid_solid() || genus(cr) != genus(in_report) || folded_faces(col, input, query) > 0) continue;
    TriMesh relaxed = col;
    relax_on_surface(relaxed, query, kRelaxIterations);
    restore_volume(relaxed, input_volume);
    if (check_mesh(relaxed).valid_solid() && folded_faces(relaxed, input, query) == 0) {
      col = std::move(relaxed);
    } else {
      restore_volume(col, input_volume);
      if (!check_mesh(col).valid_solid() || folded_faces(col, input, query) > 0) continue;
    }
    st.collapsed = true;
    st.mean_edge_m = mean_edge(col);
    if (stats) *stats = st;
    return col;
  }
  // Not even that: the refined input is a valid answer, only denser than asked for.
  st.fell_back = true;
  st.mean_edge_m = mean_edge(out);
  if (stats) *stats = st;
  return out;
}

}  // namespace ps
