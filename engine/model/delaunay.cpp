#include "engine/model/delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <algorithm>

namespace ps {

std::vector<std::array<int, 4>> delaunay_tetrahedra(const std::vector<Vec3>& points) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, K>;
  using Tds = CGAL::Triangulation_data_structure_3<Vb>;
  using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;
  std::vector<std::array<int, 4>> out;
  if (points.size() < 4) return out;
  std::vector<std::pair<K::Point_3, int>> pts;
  pts.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    pts.emplace_back(K::Point_3(points[i].x(), points[i].y(), points[i].z()), static_cast<int>(i));
  // range insertion (spatially sorted first: fast; deterministic for a given input)
  Delaunay dt(pts.begin(), pts.end());
  if (dt.dimension() < 3) return out;
  out.reserve(dt.number_of_finite_cells());
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    std::array<int, 4> t{c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()};
    const Vec3 a = points[t[1]] - points[t[0]], b = points[t[2]] - points[t[0]], d = points[t[3]] - points[t[0]];
    if (a.dot(b.cross(d)) < 0.0) std::swap(t[2], t[3]);
    out.push_back(t);
  }
  // cell iteration order depends on the data structure's memory layout: sort for a canonical order
  for (auto& t : out) {
    // rotate so the smallest index comes first while keeping the orientation (even permutations)
    int k = static_cast<int>(std::min_element(t.begin(), t.end()) - t.begin());
    static constexpr int even[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};
    std::array<int, 4> r{t[even[k][0]], t[even[k][1]], t[even[k][2]], t[even[k][3]]};
    t = r;
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace ps
