#include "engine/mesh/edge_collapse.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>
#include <vector>

namespace ps {

namespace {

// A collapse may turn a neighbouring face by at most ~70 degrees ...
constexpr double kMinNormalCos = 0.34;
// ... and must not leave it a sliver: quality 4 sqrt(3) area / sum of squared edges (1 for an
// equilateral triangle) above this.
constexpr double kMinQuality = 0.05;

double quality(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double l2 = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return l2 > 0 ? 2.0 * std::sqrt(3.0) * (b - a).cross(c - a).norm() / l2 : 0.0;
}

struct Edge {
  double len;
  int a, b;
  bool operator>(const Edge& o) const { return len != o.len ? len > o.len : (a != o.a ? a > o.a : b > o.b); }
};

class Collapser {
 public:
  explicit Collapser(const TriMesh& m) : pos_(m.vertices), faces_(m.faces), alive_(m.faces.size(), 1), vf_(m.vertices.size()) {
    for (size_t f = 0; f < faces_.size(); ++f)
      for (int v : faces_[f]) vf_[v].push_back(static_cast<int>(f));
  }

  TriMesh run(double min_edge, CollapseStats& st) {
    std::priority_queue<Edge, std::vector<Edge>, std::greater<Edge>> q;
    for (const auto& t : faces_)
      for (int k = 0; k < 3; ++k) push(q, t[k], t[(k + 1) % 3], min_edge);
    while (!q.empty()) {
      const Edge e = q.top();
      q.pop();
      if (vf_[e.a].empty() || vf_[e.b].empty() || (pos_[e.a] - pos_[e.b]).norm() != e.len) continue;  // stale
      if (!collapse(e.a, e.b)) {
        ++st.refused;
        continue;
      }
      ++st.collapses;
      for (int n : neighbours(e.a)) push(q, e.a, n, min_edge);
    }
    TriMesh out;
    std::vector<int> id(pos_.size(), -1);
    for (size_t f = 0; f < faces_.size(); ++f) {
      if (!alive_[f]) continue;
      std::array<int, 3> t = faces_[f];
      for (int& v : t) {
        if (id[v] < 0) {
          id[v] = static_cast<int>(out.vertices.size());
          out.vertices.push_back(pos_[v]);
        }
        v = id[v];
      }
      out.faces.push_back(t);
    }
    return out;
  }

 private:
  void push(std::priority_queue<Edge, std::vector<Edge>, std::greater<Edge>>& q, int a, int b, double min_edge) const {
    if (a > b) std::swap(a, b);
    const double len = (pos_[a] - pos_[b]).norm();
    if (len < min_edge) q.push({len, a, b});
  }

  std::vector<int> neighbours(int v) const {
    std::vector<int> n;
    for (int f : vf_[v])
      for (int w : faces_[f])
        if (w != v) n.push_back(w);
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    return n;
  }

  // Merges b into a at the edge midpoint; false (nothing changed) when that is not safe.
  bool collapse(int a, int b) {
    std::vector<int> shared, opposite;
    for (int f : vf_[a]) {
      const auto& t = faces_[f];
      if (std::find(t.begin(), t.end(), b) == t.end()) continue;
      shared.push_back(f);
      for (int w : t)
        if (w != a && w != b) opposite.push_back(w);
    }
    if (shared.size() != 2) return false;
    // link condition: a and b have exactly the two opposite vertices as common neighbours
    const std::vector<int> na = neighbours(a), nb = neighbours(b);
    std::vector<int> common;
    std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
    if (common.size() != 2) return false;
    // every vertex keeps at least three faces (the opposite ones lose one each, a+b lose two)
    for (int c : opposite)
      if (vf_[c].size() <= 3) return false;
    if (vf_[a].size() + vf_[b].size() < 7) return false;
    const Vec3 p = 0.5 * (pos_[a] + pos_[b]);
    for (int v : {a, b})
      for (int f : vf_[v]) {
        if (f == shared[0] || f == shared[1]) continue;
        const auto& t = faces_[f];
        const Vec3 x0 = pos_[t[0]], x1 = pos_[t[1]], x2 = pos_[t[2]];
        auto moved = [&](int w, const Vec3& x) { return (w == a || w == b) ? p : x; };
        const Vec3 y0 = moved(t[0], x0), y1 = moved(t[1], x1), y2 = moved(t[2], x2);
        const Vec3 n0 = (x1 - x0).cross(x2 - x0), n1 = (y1 - y0).cross(y2 - y0);
        if (!(n1.norm() > 0) || n0.dot(n1) < kMinNormalCos * n0.norm() * n1.norm()) return false;
        if (quality(y0, y1, y2) < kMinQuality) return false;
      }
    alive_[shared[0]] = alive_[shared[1]] = 0;
    std::vector<int> merged;
    for (int f : vf_[a])
      if (alive_[f]) merged.push_back(f);
    for (int f : vf_[b]) {
      if (!alive_[f]) continue;
      for (int& w : faces_[f])
        if (w == b) w = a;
      merged.push_back(f);
    }
    vf_[a] = std::move(merged);
    vf_[b].clear();
    for (int c : opposite) {
      auto& l = vf_[c];
      l.erase(std::remove_if(l.begin(), l.end(), [&](int f) { return !alive_[f]; }), l.end());
    }
    pos_[a] = p;
    return true;
  }

  std::vector<Vec3> pos_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<char> alive_;
  std::vector<std::vector<int>> vf_;   // vertex -> its live faces
};

}  // namespace

TriMesh collapse_short_edges(const TriMesh& m, double min_edge, CollapseStats* stats) {
  if (!(min_edge > 0) || !std::isfinite(min_edge))
    throw std::invalid_argument("collapse_short_edges: edge length must be positive and finite");
  CollapseStats st;
  TriMesh out = Collapser(m).run(min_edge, st);
  if (stats) *stats = st;
  return out;
}

}  // namespace ps
