// Elastic force of the tet model (material `model: tet`, docs/model.md "Tet model"): linear
// tetrahedra over a Delaunay tetrahedralisation of the particles (Model::tets), with
//   E = sum_t V0_t mu_t [ 1/2 (|F_t|^2 - 3) - (J_t - 1) ]          shear, per element
//     + sum_n 1/2 kappa_n V0_n (J_n - 1)^2                           volume, per node
// F_t = sum_i (x_i - x_0) g_i^T the element's deformation gradient, J_t = det F_t, and
// J_n = V_n / V0_n the volume ratio of node n's share (a quarter of each element around it).
// The shear term is the deviatoric part of the "stable neo-Hookean" energy (Smith, de Goes, Kim
// 2018): stress-free at rest, invariant under rotation, polynomial (finite for inverted or
// collapsed elements, no log J), and with kappa = lambda + mu it linearises to Hooke's law
// mu |eps|^2 + lambda/2 (tr eps)^2. Volume is measured per node, not per element (the averaged
// nodal pressure of Bonet & Burton 1998): per-element J with a large kappa locks linear tets
// (every tet has to keep its own volume), the nodal average does not.
// Gradient: dE/dx_i = V0_t P_t g_i for the element's own vertices (g_0 = -g_1 - g_2 - g_3), with
//   P_t = mu_t (F - cof F) + pbar_t cof F,   pbar_t = mean over t's 4 nodes of kappa_n (J_n - 1)
// because dV_t/dx_i = V0_t cof(F_t) g_i and dJ_n/dx_i = sum_{t around n} dV_t/dx_i / (4 V0_n).
// Three passes: node volumes, node pressures, element forces. Forces sum to zero per element
// (momentum) and the energy is rotation invariant (angular momentum). No allocation: the node
// scratch is State::tet_node_vol, sized at make_state.
#include "engine/step/stages.h"

namespace ps {

namespace {

struct ElementKinematics {
  Mat3 F;    // deformation gradient [-]
  Mat3 cof;  // cofactor of F = dJ/dF [-]
};

inline ElementKinematics kinematics(const TetElements& te, const std::vector<Vec3>& x, int t) {
  const int* v = &te.v[4 * t];
  const double* g = &te.g[9 * t];
  const Vec3 x0 = x[v[0]];
  const Vec3 e1 = x[v[1]] - x0, e2 = x[v[2]] - x0, e3 = x[v[3]] - x0;
  ElementKinematics k;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) k.F(r, c) = e1[r] * g[c] + e2[r] * g[3 + c] + e3[r] * g[6 + c];
  k.cof.col(0) = k.F.col(1).cross(k.F.col(2));
  k.cof.col(1) = k.F.col(2).cross(k.F.col(0));
  k.cof.col(2) = k.F.col(0).cross(k.F.col(1));
  return k;
}

// current volume share V_n of every tet node into vol (indexed like te.nodes)
void node_volumes(const TetElements& te, const std::vector<Vec3>& x, double* vol) {
  const int nn = static_cast<int>(te.nodes.size());
  for (int a = 0; a < nn; ++a) vol[a] = 0.0;
  const int nt = te.count();
  for (int t = 0; t < nt; ++t) {
    const int* v = &te.v[4 * t];
    const Vec3 x0 = x[v[0]];
    const double quarter = (x[v[1]] - x0).dot((x[v[2]] - x0).cross(x[v[3]] - x0)) / 24.0;  // V_t / 4
    for (int i = 0; i < 4; ++i) vol[te.node_slot[v[i]]] += quarter;
  }
}

}  // namespace

void add_tet_elastic_forces(const Model& m, State& s) {
  const TetElements& te = m.tets;
  double* p = s.tet_node_vol.data();
  node_volumes(te, s.x, p);
  const int nn = static_cast<int>(te.nodes.size());
  for (int a = 0; a < nn; ++a) p[a] = te.node_kappa[a] * (p[a] * te.node_inv_vol0[a] - 1.0);  // pressure [Pa]
  const int nt = te.count();
  for (int t = 0; t < nt; ++t) {
    const int* v = &te.v[4 * t];
    const double* g = &te.g[9 * t];
    const ElementKinematics k = kinematics(te, s.x, t);
    const double pbar = 0.25 * (p[te.node_slot[v[0]]] + p[te.node_slot[v[1]]] + p[te.node_slot[v[2]]] + p[te.node_slot[v[3]]]);
    const double mu = te.mu[t];
    const Mat3 P = (te.vol0[t] * mu) * k.F + (te.vol0[t] * (pbar - mu)) * k.cof;  // V0 x first Piola stress [N m]
    const Vec3 f1 = -(P * Vec3(g[0], g[1], g[2]));
    const Vec3 f2 = -(P * Vec3(g[3], g[4], g[5]));
    const Vec3 f3 = -(P * Vec3(g[6], g[7], g[8]));
    s.f[v[1]] += f1;
    s.f[v[2]] += f2;
    s.f[v[3]] += f3;
    s.f[v[0]] -= f1 + f2 + f3;
  }
}

double tet_elastic_energy(const Model& m, const State& s) {
  const TetElements& te = m.tets;
  std::vector<double> vol(te.nodes.size());
  node_volumes(te, s.x, vol.data());
  double e = 0.0;
  for (int t = 0; t < te.count(); ++t) {
    const ElementKinematics k = kinematics(te, s.x, t);
    e += te.vol0[t] * te.mu[t] * (0.5 * (k.F.squaredNorm() - 3.0) - (k.F.determinant() - 1.0));
  }
  for (size_t a = 0; a < te.nodes.size(); ++a) {
    const double j = vol[a] * te.node_inv_vol0[a];
    e += 0.5 * te.node_kappa[a] / te.node_inv_vol0[a] * (j - 1.0) * (j - 1.0);
  }
  return e;
}

}  // namespace ps
