#include "engine/model/tet_elements.h"

#include <algorithm>
#include <cmath>

#include "engine/model/delaunay.h"
#include "engine/util/error.h"

namespace ps {

double winding_number(const std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& pos, const Vec3& q) {
  double w = 0.0;
  for (const auto& f : faces) {
    const Vec3 a = pos[f[0]] - q, b = pos[f[1]] - q, c = pos[f[2]] - q;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    w += 2.0 * std::atan2(num, den);
  }
  return w / (4.0 * 3.14159265358979323846);
}

namespace {

struct Candidate {
  std::array<int, 4> v;  // global particle indices
};

// Quality and hull filters shared by component and interface elements; true when kept.
bool acceptable(const Model& m, const std::array<int, 4>& v, double spacing, int& slivers, int& long_edges) {
  const Vec3* x[4] = {&m.rest_pos[v[0]], &m.rest_pos[v[1]], &m.rest_pos[v[2]], &m.rest_pos[v[3]]};
  double mean = 0.0, longest = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double l = (*x[i] - *x[j]).norm();
      mean += l / 6.0;
      longest = std::max(longest, l);
    }
  if (longest > kTetMaxEdgeSpacings * spacing) { ++long_edges; return false; }
  const double vol = (*x[1] - *x[0]).dot((*x[2] - *x[0]).cross(*x[3] - *x[0])) / 6.0;
  if (!(vol > kTetSliverQuality * mean * mean * mean)) { ++slivers; return false; }
  return true;
}

}  // namespace

std::vector<std::string> build_tet_elements(Model& m, const std::vector<TetParticle>& mat,
                                            const std::vector<std::vector<int>>& excluded,
                                            const std::vector<TetLink>& links) {
  std::vector<std::string> warnings;
  const int n = m.particle_count();
  std::vector<std::array<int, 4>> elems;
  for (size_t ci = 0; ci < m.components.size(); ++ci) {
    const Component& comp = m.components[ci];
    const int b = comp.first_particle, e = b + comp.particle_count;
    if (comp.particle_count == 0 || !(mat[b].mu > 0.0)) continue;
    std::vector<Vec3> pts(m.rest_pos.begin() + b, m.rest_pos.begin() + e);
    int slivers = 0, long_edges = 0, outside = 0;
    const size_t before = elems.size();
    const Surface* surf = comp.surface >= 0 ? &m.surfaces[comp.surface] : nullptr;
    for (const auto& t : delaunay_tetrahedra(pts)) {
      const std::array<int, 4> v{t[0] + b, t[1] + b, t[2] + b, t[3] + b};
      if (!acceptable(m, v, comp.spacing, slivers, long_edges)) continue;
      const Vec3 c = 0.25 * (m.rest_pos[v[0]] + m.rest_pos[v[1]] + m.rest_pos[v[2]] + m.rest_pos[v[3]]);
      // only an element with every vertex on the surface can lie outside a closed surface it
      // does not cross (the Delaunay hull of a concave shape); test those
      bool all_surface = true;
      for (int i : v) all_surface &= m.on_surface[i] != 0;
      if (all_surface && surf && winding_number(surf->faces, m.rest_pos, c) < 0.5) { ++outside; continue; }
      bool in_hole = false;
      for (int sid : excluded[ci]) in_hole |= winding_number(m.surfaces[sid].faces, m.rest_pos, c) > 0.5;
      if (in_hole) { ++outside; continue; }
      elems.push_back(v);
    }
    if (elems.size() == before)
      throw CompileError("component '" + comp.name + "': the tet model found no element (needs a volumetric fill)");
    if (slivers + long_edges > 0)
      warnings.push_back("component '" + comp.name + "': tet model left out " + std::to_string(slivers) +
                         " sliver and " + std::to_string(long_edges) + " hull elements of " +
                         std::to_string(elems.size() - before + slivers + long_edges + outside));
  }
  // interfaces: the Delaunay elements of the particles near both sides that have vertices in both
  for (const TetLink& l : links) {
    const Component& A = m.components[l.a];
    const Component& B = m.components[l.b];
    std::vector<int> near;  // global indices
    auto collect = [&](const Component& P, const Component& Q) {
      for (int p = P.first_particle; p < P.first_particle + P.particle_count; ++p)
        for (int q = Q.first_particle; q < Q.first_particle + Q.particle_count; ++q)
          if ((m.rest_pos[p] - m.rest_pos[q]).squaredNorm() < l.distance * l.distance) { near.push_back(p); break; }
    };
    collect(A, B);
    collect(B, A);
    if (near.size() < 4) continue;
    std::vector<Vec3> pts;
    for (int p : near) pts.push_back(m.rest_pos[p]);
    const double spacing = std::max(A.spacing, B.spacing);
    int slivers = 0, long_edges = 0, made = 0;
    for (const auto& t : delaunay_tetrahedra(pts)) {
      const std::array<int, 4> v{near[t[0]], near[t[1]], near[t[2]], near[t[3]]};
      int in_a = 0;
      for (int i : v) in_a += m.component_of[i] == l.a;
      if (in_a == 0 || in_a == 4) continue;  // inside one component: it has its own elements
      if (!acceptable(m, v, spacing, slivers, long_edges)) continue;
      elems.push_back(v);
      ++made;
    }
    if (made == 0)
      warnings.push_back("link " + A.name + " - " + B.name + ": no tet element spans the interface");
  }
  // rest data
  TetElements& te = m.tets;
  te = TetElements{};
  te.node_slot.assign(n, -1);
  std::vector<double> node_vol(n, 0.0);
  for (const auto& v : elems) {
    Mat3 Dm;
    for (int i = 0; i < 3; ++i) Dm.col(i) = m.rest_pos[v[i + 1]] - m.rest_pos[v[0]];
    const Mat3 G = Dm.inverse();  // rows g1, g2, g3
    const double vol = Dm.determinant() / 6.0;
    // an interface element: the mean of both sides, or of the tet side's vertices when the other
    // side is a shell wall (mu = 0 here: its stiffness is its own elements')
    double mu = 0.0, sum = 0.0;
    int with_mu = 0;
    for (int i : v) { mu += 0.25 * mat[i].mu; sum += mat[i].mu; with_mu += mat[i].mu > 0.0; }
    if (with_mu < 4) mu = with_mu > 0 ? sum / with_mu : 0.0;
    for (int i : v) { te.v.push_back(i); node_vol[i] += 0.25 * vol; }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) te.g.push_back(G(r, c));
    te.vol0.push_back(vol);
    te.mu.push_back(mu);
  }
  te.fast_count = te.count();  // every element every substep until partition_tet_rates (compile.cpp)
  int orphans = 0;
  for (int p = 0; p < n; ++p) {
    if (node_vol[p] > 0.0) {
      te.node_slot[p] = static_cast<int>(te.nodes.size());
      te.nodes.push_back(p);
      te.node_inv_vol0.push_back(1.0 / node_vol[p]);
      te.node_kappa.push_back(mat[p].lambda + mat[p].mu);
      te.node_implicit.push_back(mat[p].implicit_pressure ? 1 : 0);
      te.node_kappa_explicit.push_back(mat[p].implicit_pressure ? 0.0 : mat[p].lambda + mat[p].mu);
    } else if (mat[p].mu > 0.0) {
      ++orphans;
    }
  }
  if (orphans > 0)
    warnings.push_back("tet model: " + std::to_string(orphans) + " particle(s) belong to no element and carry no elastic force");
  return warnings;
}

void pack_tet_blocks(TetElements& te) {
  const int nt = te.count();
  const int blocks = (nt + 3) / 4;
  te.g4.assign(36 * static_cast<size_t>(blocks), 0.0);
  for (int t = 0; t < nt; ++t)
    for (int i = 0; i < 9; ++i) te.g4[36 * (t / 4) + 4 * i + t % 4] = te.g[9 * t + i];
  const int nn = static_cast<int>(te.nodes.size());
  // each node's elements, ascending (CSR: node_elem[start[a] .. start[a + 1]), the fast ones
  // before mid[a]), then laid out in bundles of four nodes (TetElements::gather_*)
  std::vector<int> start(nn + 1, 0);
  for (int v : te.v) ++start[te.node_slot[v] + 1];
  for (int a = 0; a < nn; ++a) start[a + 1] += start[a];
  std::vector<int> fill(start.begin(), start.end() - 1);
  std::vector<int> node_elem(te.v.size(), 0);
  for (int t = 0; t < nt; ++t)  // ascending t: each node's list comes out ascending
    for (int i = 0; i < 4; ++i) node_elem[fill[te.node_slot[te.v[4 * t + i]]]++] = t;
  std::vector<int> mid(nn, 0);
  for (int a = 0; a < nn; ++a) {
    int e = start[a];
    while (e < start[a + 1] && node_elem[e] < te.fast_count) ++e;
    mid[a] = e;
  }
  const int bundles = (nn + 3) / 4;
  for (int r = 0; r < 3; ++r) {
    te.gather_start[r].assign(1, 0);
    te.gather_elem[r].clear();
    for (int b = 0; b < bundles; ++b) {
      int lo[4], len[4], rows = 0;
      for (int l = 0; l < 4; ++l) {
        const int a = 4 * b + l;
        lo[l] = len[l] = 0;
        if (a >= nn) continue;
        lo[l] = r == 2 ? mid[a] : start[a];
        len[l] = (r == 1 ? mid[a] : start[a + 1]) - lo[l];
        rows = std::max(rows, len[l]);
      }
      for (int j = 0; j < rows; ++j)
        for (int l = 0; l < 4; ++l) te.gather_elem[r].push_back(j < len[l] ? node_elem[lo[l] + j] : nt);
      te.gather_start[r].push_back(te.gather_start[r].back() + rows);
    }
  }
}

}  // namespace ps
