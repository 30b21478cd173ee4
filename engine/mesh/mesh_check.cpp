#include "engine/mesh/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "engine/util/error.h"

namespace ps {
namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// One face's use of an undirected edge; forward means the face walks it from the lower vertex
// index to the higher one.
struct EdgeUse {
  uint64_t key;
  int face;
  int corner;   // position 0..2 of the edge's first vertex in the face
  bool forward;
};

uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<uint32_t>(std::min(a, b)), hi = static_cast<uint32_t>(std::max(a, b));
  return (uint64_t(lo) << 32) | hi;
}
int key_lo(uint64_t k) { return static_cast<int>(k >> 32); }
int key_hi(uint64_t k) { return static_cast<int>(k & 0xffffffffu); }

// Edge uses of the faces flagged in `use`, sorted so that the uses of one edge are adjacent.
std::vector<EdgeUse> edge_uses(const TriMesh& m, const std::vector<char>& use) {
  std::vector<EdgeUse> e;
  e.reserve(3 * m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f) {
    if (!use[f]) continue;
    const auto& t = m.faces[f];
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      e.push_back({edge_key(a, b), static_cast<int>(f), k, a < b});
    }
  }
  std::sort(e.begin(), e.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.face < y.face;
  });
  return e;
}

bool valid_indices(const std::array<int, 3>& f, size_t nv) {
  return f[0] >= 0 && f[1] >= 0 && f[2] >= 0 && size_t(f[0]) < nv && size_t(f[1]) < nv &&
         size_t(f[2]) < nv;
}
bool repeated(const std::array<int, 3>& f) { return f[0] == f[1] || f[1] == f[2] || f[0] == f[2]; }

// Bounding box of the finite vertices: {centre, diagonal [m]}.
std::pair<Vec3, double> bbox(const TriMesh& m) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const Vec3& v : m.vertices)
    if (v.allFinite()) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  if (!(lo.array() <= hi.array()).all()) return {Vec3::Zero(), 0.0};
  return {0.5 * (lo + hi), (hi - lo).norm()};
}

double face_area(const TriMesh& m, const std::array<int, 3>& f) {
  const Vec3& a = m.vertices[f[0]];
  return 0.5 * (m.vertices[f[1]] - a).cross(m.vertices[f[2]] - a).norm();
}

// Volume contribution of one face, relative to `o` to limit cancellation far from the origin.
double face_volume6(const TriMesh& m, const std::array<int, 3>& f, const Vec3& o) {
  return (m.vertices[f[0]] - o).dot((m.vertices[f[1]] - o).cross(m.vertices[f[2]] - o));
}

std::string edge_str(int a, int b) { return std::to_string(a) + "-" + std::to_string(b); }

}  // namespace

std::string MeshReport::summary() const {
  std::ostringstream s;
  s << vertices << " vertices, " << faces << " faces, " << components << " component(s)";
  if (invalid_faces) s << "; " << invalid_faces << " faces with invalid indices (first face " << first_invalid_face << ")";
  if (non_finite_vertices) s << "; " << non_finite_vertices << " non-finite vertices";
  if (boundary_edges)
    s << "; open: " << boundary_edges << " boundary edges (first " << edge_str(first_boundary_edge[0], first_boundary_edge[1]) << ")";
  if (non_manifold_edges)
    s << "; " << non_manifold_edges << " non-manifold edges (first "
      << edge_str(first_non_manifold_edge[0], first_non_manifold_edge[1]) << ")";
  if (non_manifold_vertices)
    s << "; " << non_manifold_vertices << " non-manifold vertices (first " << first_non_manifold_vertex << ")";
  if (degenerate_faces) s << "; " << degenerate_faces << " degenerate faces (first face " << first_degenerate_face << ")";
  if (inconsistent_edges)
    s << "; inconsistent orientation at " << inconsistent_edges << " edges (first "
      << edge_str(first_inconsistent_edge[0], first_inconsistent_edge[1]) << ")";
  if (inverted) s << "; inverted (negative volume)";
  if (unreferenced_vertices) s << "; " << unreferenced_vertices << " unreferenced vertices";
  if (valid_solid()) s << "; closed 2-manifold, outward, volume " << signed_volume << " m^3";
  return s.str();
}

MeshReport check_mesh(const TriMesh& m, double degenerate_area_rel) {
  MeshReport r;
  const size_t nv = m.vertices.size(), nf = m.faces.size();
  r.vertices = static_cast<int>(nv);
  r.faces = static_cast<int>(nf);
  for (const Vec3& v : m.vertices) r.non_finite_vertices += v.allFinite() ? 0 : 1;
  const auto [centre, diag] = bbox(m);
  const double area_tol = degenerate_area_rel * diag * diag;

  std::vector<char> in_edges(nf, 0), referenced(nv, 0);
  double vol6 = 0.0;
  for (size_t f = 0; f < nf; ++f) {
    const auto& t = m.faces[f];
    if (!valid_indices(t, nv)) {
      if (r.invalid_faces++ == 0) r.first_invalid_face = static_cast<int>(f);
      continue;
    }
    for (int k = 0; k < 3; ++k) referenced[t[k]] = 1;
    // A face with a repeated index has no proper edges; keep it out of the edge statistics so
    // that it shows up once, as degenerate, rather than as spurious boundary edges.
    const bool rep = repeated(t);
    const double a = rep ? 0.0 : face_area(m, t);
    if (rep || !(a >= area_tol) || a == 0.0) {
      if (r.degenerate_faces++ == 0) r.first_degenerate_face = static_cast<int>(f);
    }
    if (rep) continue;
    in_edges[f] = 1;
    r.area += a;
    vol6 += face_volume6(m, t, centre);
  }
  r.signed_volume = vol6 / 6.0;
  for (size_t v = 0; v < nv; ++v) r.unreferenced_vertices += referenced[v] ? 0 : 1;

  const std::vector<EdgeUse> e = edge_uses(m, in_edges);
  UnionFind corners(3 * nf);
  UnionFind verts(nv);
  for (size_t i = 0; i < e.size();) {
    size_t j = i;
    while (j < e.size() && e[j].key == e[i].key) ++j;
    const size_t n = j - i;
    const int a = key_lo(e[i].key), b = key_hi(e[i].key);
    verts.unite(a, b);
    if (n == 1) {
      if (r.boundary_edges++ == 0) r.first_boundary_edge = {a, b};
    } else if (n > 2) {
      if (r.non_manifold_edges++ == 0) r.first_non_manifold_edge = {a, b};
    } else {
      if (e[i].forward == e[i + 1].forward && r.inconsistent_edges++ == 0)
        r.first_inconsistent_edge = {a, b};
      // The two faces are neighbours around both end vertices: join their corners there.
      const int f0 = e[i].face, f1 = e[i + 1].face;
      for (int v : {a, b}) {
        int c0 = -1, c1 = -1;
        for (int k = 0; k < 3; ++k) {
          if (m.faces[f0][k] == v) c0 = 3 * f0 + k;
          if (m.faces[f1][k] == v) c1 = 3 * f1 + k;
        }
        corners.unite(c0, c1);
      }
    }
    i = j;
  }
  // A vertex is manifold when all its corners form one fan.
  std::vector<int> fan(nv, -1);
  std::vector<char> marked(nv, 0);
  for (size_t f = 0; f < nf; ++f) {
    if (!in_edges[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const int v = m.faces[f][k];
      const int root = corners.find(static_cast<int>(3 * f + k));
      if (fan[v] < 0) fan[v] = root;
      else if (fan[v] != root && !marked[v]) {
        marked[v] = 1;
        if (r.non_manifold_vertices++ == 0) r.first_non_manifold_vertex = v;
      }
    }
  }
  // Components: faces joined through shared vertices (also joins the vertices of faces that
  // were kept out of the edge statistics).
  for (size_t f = 0; f < nf; ++f) {
    const auto& t = m.faces[f];
    if (!valid_indices(t, nv)) continue;
    verts.unite(t[0], t[1]);
    verts.unite(t[1], t[2]);
  }
  for (size_t v = 0; v < nv; ++v)
    if (referenced[v] && verts.find(static_cast<int>(v)) == static_cast<int>(v)) ++r.components;

  r.inverted = r.closed() && r.inconsistent_edges == 0 && r.signed_volume < 0.0;
  return r;
}

int remove_collapsed_and_duplicate_faces(TriMesh& m, std::vector<int>* kept_from) {
  const size_t nf0 = m.faces.size();
  std::vector<int> orig;
  orig.reserve(nf0);
  // A face with a repeated vertex walks its one real edge both ways: removing it leaves every
  // other edge's face count and direction balance unchanged, so it is always safe.
  {
    size_t w = 0;
    for (size_t f = 0; f < nf0; ++f)
      if (!repeated(m.faces[f])) {
        m.faces[w++] = m.faces[f];
        orig.push_back(static_cast<int>(f));
      }
    m.faces.resize(w);
  }
  // Faces over the same three vertices: keep as many as the rest of the surface needs, i.e.
  // one when each of the three edges has exactly one face outside the group (oriented against
  // those faces), none when each has two (the group is a sheet glued onto a closed surface) or
  // none at all (a detached pillow). Anything else is left for validation to report.
  std::unordered_map<uint64_t, int> directed;   // (a << 32 | b) -> faces walking a->b
  directed.reserve(3 * m.faces.size());
  auto dkey = [](int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); };
  for (const auto& t : m.faces)
    for (int k = 0; k < 3; ++k) ++directed[dkey(t[k], t[(k + 1) % 3])];
  struct Key {
    std::array<int, 3> s;   // smallest index first, then ascending: (s0, s1, s2)
    int sign;               // +1 if the face walks s0 -> s1 -> s2, -1 if s0 -> s2 -> s1
    int idx;
  };
  std::vector<Key> keys(m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f) {
    auto t = m.faces[f];
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    const int sign = t[1] < t[2] ? 1 : -1;
    if (sign < 0) std::swap(t[1], t[2]);
    keys[f] = {t, sign, static_cast<int>(f)};
  }
  std::sort(keys.begin(), keys.end(),
            [](const Key& a, const Key& b) { return a.s != b.s ? a.s < b.s : a.idx < b.idx; });
  std::vector<char> keep(m.faces.size(), 1);
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    int plus = 0;
    while (j < keys.size() && keys[j].s == keys[i].s) plus += keys[j++].sign > 0;
    const int g = static_cast<int>(j - i), minus = g - plus;
    if (g > 1) {
      const auto& s = keys[i].s;
      // Per edge of the +1 walk (s0->s1, s1->s2, s2->s0): faces outside the group walking it
      // forward and backward.
      int outside_min = 1 << 30, outside_max = 0, vote = 0;
      for (int k = 0; k < 3; ++k) {
        const int a = s[k], b = s[(k + 1) % 3];
        const int fwd = directed[dkey(a, b)] - plus, bwd = directed[dkey(b, a)] - minus;
        outside_min = std::min(outside_min, fwd + bwd);
        outside_max = std::max(outside_max, fwd + bwd);
        vote += bwd - fwd;   // the kept face must walk each edge against its outside neighbour
      }
      int keep_sign = 0;   // 0: keep none
      bool resolved = true;
      if (outside_min == 1 && outside_max == 1)
        keep_sign = vote > 0 ? 1 : vote < 0 ? -1 : (plus >= minus ? 1 : -1);
      else if (!(outside_max == 0 || (outside_min == 2 && outside_max == 2)))
        resolved = false;
      if (resolved) {
        bool kept_one = false;
        for (size_t k = i; k < j; ++k) {
          if (!kept_one && keys[k].sign == keep_sign) kept_one = true;
          else keep[keys[k].idx] = 0;
        }
        if (keep_sign != 0 && !kept_one) {
          // Only the other orientation is present: keep one of them, reversed.
          keep[keys[i].idx] = 1;
          auto& t = m.faces[keys[i].idx];
          std::swap(t[1], t[2]);
        }
      }
    }
    i = j;
  }
  size_t w = 0;
  for (size_t f = 0; f < m.faces.size(); ++f)
    if (keep[f]) {
      m.faces[w] = m.faces[f];
      orig[w++] = orig[f];
    }
  m.faces.resize(w);
  orig.resize(w);
  if (kept_from) *kept_from = std::move(orig);
  return static_cast<int>(nf0 - w);
}

TriMesh repair_closed_surface(TriMesh mesh, const std::string& file, RepairStats* stats) {
  RepairStats st;
  const size_t nv = mesh.vertices.size();
  if (mesh.faces.empty()) throw InputError(file, 0, "", "surface has no faces");
  for (size_t v = 0; v < nv; ++v)
    if (!mesh.vertices[v].allFinite())
      throw InputError(file, 0, "", "vertex " + std::to_string(v) + " has a non-finite coordinate");
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    if (!valid_indices(mesh.faces[f], nv))
      throw InputError(file, 0, "", "face " + std::to_string(f) + " refers to a vertex out of range (mesh has " +
                                        std::to_string(nv) + " vertices)");
  const auto [centre, diag] = bbox(mesh);

  // 1. Weld: hash vertices into cells of the tolerance and compare with the 27 neighbour cells.
  const double tol = kWeldRel * diag;
  std::vector<int> remap(nv);
  std::vector<Vec3> welded;
  if (tol > 0) {
    struct CellHash {
      size_t operator()(const std::array<int64_t, 3>& c) const {
        return static_cast<size_t>((c[0] * 73856093) ^ (c[1] * 19349663) ^ (c[2] * 83492791));
      }
    };
    std::unordered_map<std::array<int64_t, 3>, std::vector<int>, CellHash> cells;
    cells.reserve(nv);
    for (size_t v = 0; v < nv; ++v) {
      const Vec3 q = (mesh.vertices[v] - centre) / tol;
      const std::array<int64_t, 3> c{int64_t(std::floor(q.x())), int64_t(std::floor(q.y())), int64_t(std::floor(q.z()))};
      int found = -1;
      for (int dx = -1; dx <= 1 && found < 0; ++dx)
        for (int dy = -1; dy <= 1 && found < 0; ++dy)
          for (int dz = -1; dz <= 1 && found < 0; ++dz) {
            auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == cells.end()) continue;
            for (int w : it->second)
              if ((welded[w] - mesh.vertices[v]).norm() <= tol) {
                found = w;
                break;
              }
          }
      if (found < 0) {
        found = static_cast<int>(welded.size());
        welded.push_back(mesh.vertices[v]);
        cells[c].push_back(found);
      } else {
        ++st.merged_vertices;
      }
      remap[v] = found;
    }
  } else {
    welded = mesh.vertices;
    std::iota(remap.begin(), remap.end(), 0);
  }

  // 2. Remap, then drop collapsed faces and resolve duplicates.
  TriMesh m;
  m.vertices = std::move(welded);
  m.faces = mesh.faces;
  for (auto& t : m.faces)
    for (int& i : t) i = remap[i];
  std::vector<int> orig;   // input face index of each kept face, for error messages
  st.dropped_faces = remove_collapsed_and_duplicate_faces(m, &orig);
  if (m.faces.empty()) throw InputError(file, 0, "", "surface has no faces left after removing collapsed ones");

  // 4. Refuse what cannot be repaired safely.
  const std::vector<char> all(m.faces.size(), 1);
  const std::vector<EdgeUse> e = edge_uses(m, all);
  int boundary = 0, non_manifold = 0;
  uint64_t first_boundary = 0, first_nm = 0;
  for (size_t i = 0; i < e.size();) {
    size_t j = i;
    while (j < e.size() && e[j].key == e[i].key) ++j;
    if (j - i == 1 && boundary++ == 0) first_boundary = e[i].key;
    if (j - i > 2 && non_manifold++ == 0) first_nm = e[i].key;
    i = j;
  }
  // Vertex numbers in messages refer to the welded mesh: map back to an input vertex.
  std::vector<int> input_vertex(m.vertices.size(), -1);
  for (size_t v = nv; v-- > 0;) input_vertex[remap[v]] = static_cast<int>(v);
  auto in_edge = [&](uint64_t k) { return edge_str(input_vertex[key_lo(k)], input_vertex[key_hi(k)]); };
  if (boundary > 0)
    throw InputError(file, 0, "", "open surface: " + std::to_string(boundary) +
                                      " boundary edges, first at vertices " + in_edge(first_boundary));
  if (non_manifold > 0)
    throw InputError(file, 0, "", "non-manifold surface: " + std::to_string(non_manifold) +
                                      " edges shared by more than two faces, first at vertices " +
                                      in_edge(first_nm));
  const double area_tol = kDegenerateAreaRel * diag * diag;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const double a = face_area(m, m.faces[f]);
    if (!(a >= area_tol) || a == 0.0)
    {
      // positions as well as indices: importers may renumber vertices (assimp splits and the
      // import merges them), the coordinates identify the face in the file
      char area[64];
      std::snprintf(area, sizeof area, "%.3g", a);
      std::string where;
      for (int k = 0; k < 3; ++k) {
        const Vec3& x = mesh.vertices[mesh.faces[orig[f]][k]];
        char buf[96];
        std::snprintf(buf, sizeof buf, "%s(%.6g, %.6g, %.6g)", k ? ", " : "", x.x(), x.y(), x.z());
        where += buf;
      }
      throw InputError(file, 0, "", "degenerate (zero-area) face " + std::to_string(orig[f]) + " (area " + area +
                                        " m^2): vertices " + std::to_string(mesh.faces[orig[f]][0]) + ", " +
                                        std::to_string(mesh.faces[orig[f]][1]) + ", " +
                                        std::to_string(mesh.faces[orig[f]][2]) + " at " + where + " m");
    }
  }

  // 5. Consistent orientation by a breadth-first walk over the (now all two-face) edges.
  const size_t nf = m.faces.size();
  std::vector<std::vector<std::pair<int, bool>>> nbr(nf);   // neighbour, walks edge same way
  for (size_t i = 0; i < e.size(); i += 2) {
    const bool same = e[i].forward == e[i + 1].forward;
    nbr[e[i].face].push_back({e[i + 1].face, same});
    nbr[e[i + 1].face].push_back({e[i].face, same});
  }
  std::vector<int> flip(nf, -1), queue;
  for (size_t seed = 0; seed < nf; ++seed) {
    if (flip[seed] >= 0) continue;
    flip[seed] = 0;
    queue.assign(1, static_cast<int>(seed));
    for (size_t q = 0; q < queue.size(); ++q) {
      const int f = queue[q];
      for (auto [g, same] : nbr[f]) {
        const int want = flip[f] ^ (same ? 1 : 0);
        if (flip[g] < 0) {
          flip[g] = want;
          queue.push_back(g);
        } else if (flip[g] != want) {
          throw InputError(file, 0, "", "non-orientable surface (like a Moebius strip) at face " +
                                            std::to_string(orig[g]));
        }
      }
    }
    // Outward: the component's own volume must be positive.
    double vol6 = 0.0;
    for (int f : queue) {
      auto t = m.faces[f];
      if (flip[f]) std::swap(t[1], t[2]);
      vol6 += face_volume6(m, t, centre);
    }
    if (vol6 < 0)
      for (int f : queue) flip[f] ^= 1;
  }
  for (size_t f = 0; f < nf; ++f)
    if (flip[f]) {
      std::swap(m.faces[f][1], m.faces[f][2]);
      ++st.flipped_faces;
    }

  // 6. Compact away vertices no face uses any more (keeping the input order).
  std::vector<int> newid(m.vertices.size(), -1);
  for (const auto& t : m.faces)
    for (int i : t) newid[i] = 0;
  TriMesh out;
  for (size_t v = 0; v < m.vertices.size(); ++v)
    if (newid[v] == 0) {
      newid[v] = static_cast<int>(out.vertices.size());
      out.vertices.push_back(m.vertices[v]);
    }
  for (auto& t : m.faces)
    for (int& i : t) i = newid[i];
  out.faces = std::move(m.faces);
  if (stats) *stats = st;
  return out;
}

}  // namespace ps
