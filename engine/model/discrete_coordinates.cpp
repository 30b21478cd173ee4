#include "engine/model/discrete_coordinates.h"

#include <algorithm>
#include <cmath>

#include "engine/model/triplet_chunks.h"
#include "engine/util/error.h"

namespace ps {

namespace {
std::string who(const Model& m, int p) {
  return "particle " + std::to_string(p) + " of component '" + m.components[m.component_of[p]].name + "'";
}
}  // namespace

void compute_discrete_coordinates(Model& model) {
  const int n = model.particle_count();
  model.nbr_w.assign(model.nbr.size(), 0.0);
  model.beta_start.assign(n + 1, 0);
  model.beta.clear();
  model.triplet_count.assign(n, 0);

  for (int p = 0; p < n; ++p) {
    model.beta_start[p] = static_cast<int>(model.beta.size());
    if (!model.shape_memory[p]) continue;
    const int s = model.nbr_start[p], e = model.nbr_start[p + 1], nn = e - s;
    if (nn < 3)
      throw CompileError(who(model, p) + ": only " + std::to_string(nn) +
                         " neighbours; a shape-memory particle needs at least 3 non-collinear ones");
    if (nn > kMaxNeighbours)
      throw CompileError(who(model, p) + ": " + std::to_string(nn) + " neighbours, more than the limit " +
                         std::to_string(kMaxNeighbours));
    const Vec3 P = model.rest_pos[p];
    double size = 0.0;
    for (int a = s; a < e; ++a) size = std::max(size, (model.rest_pos[model.nbr[a]] - P).norm());
    if (!(size > 0.0)) throw CompileError(who(model, p) + ": all neighbours coincide with the particle");

    // every valid triplet with its barycentric alphas, beta and conditioning score; kept in
    // enumeration order, then (solver.triplets) the best max_triplets of them
    struct Cand { int a, b, c; double ai, aj, ak, beta, score; };
    Cand cand[kMaxCandidates];
    int nc = 0;
    for (int a = s; a < e; ++a)
      for (int b = a + 1; b < e; ++b)
        for (int c = b + 1; c < e; ++c) {
          const Vec3 Ni = model.rest_pos[model.nbr[a]];
          const Vec3 Nj = model.rest_pos[model.nbr[b]];
          const Vec3 Nk = model.rest_pos[model.nbr[c]];
          const Vec3 eij = Nj - Ni, eik = Nk - Ni, ejk = Nk - Nj;
          const Vec3 nrm = eij.cross(eik);
          const double longest2 = std::max({eij.squaredNorm(), eik.squaredNorm(), ejk.squaredNorm()});
          if (nrm.norm() < kTripletQualityMin * longest2) continue;  // collinear: rejected
          const Vec3 nhat = nrm.normalized();
          const double beta = (P - Ni).dot(nhat);
          const Vec3 Q = P - beta * nhat;
          // barycentric coordinates of Q in (Ni, Nj, Nk)
          const double area2 = nrm.squaredNorm();
          // Q - Ni = aj*eij + ak*eik; crossing with eik (resp. eij) isolates aj (resp. ak)
          const double aj = (Q - Ni).cross(eik).dot(nrm) / area2;
          const double ak = eij.cross(Q - Ni).dot(nrm) / area2;
          const double ai = 1.0 - aj - ak;
          // bound on |dP*_t/dx| summed over the three vertices: the affine weights plus the
          // normal term, |beta| |opposite edge| / |n| per vertex (as needle_coupling.cpp bounds
          // an anchor). Large for slivers and for a particle far off a small triangle.
          const double ln = nrm.norm();
          const double score = std::abs(ai) + std::abs(aj) + std::abs(ak) +
                               std::abs(beta) * (ejk.norm() + eik.norm() + eij.norm()) / ln;
          cand[nc++] = Cand{a, b, c, ai, aj, ak, beta, score};
        }
    if (model.max_triplets > 0 && nc > model.max_triplets) {
      // best-conditioned first; ties by enumeration order (deterministic)
      int idx[kMaxCandidates];
      for (int i = 0; i < nc; ++i) idx[i] = i;
      std::stable_sort(idx, idx + nc, [&](int x, int y) { return cand[x].score < cand[y].score; });
      std::sort(idx, idx + model.max_triplets);  // back to enumeration order
      for (int i = 0; i < model.max_triplets; ++i) cand[i] = cand[idx[i]];
      nc = model.max_triplets;
    }
    // accumulate alpha per neighbour and the beta triplets; divide by m at the end
    int m = 0;
    const int first_beta = static_cast<int>(model.beta.size());
    for (int i = 0; i < nc; ++i) {
      const Cand& t = cand[i];
      model.nbr_w[t.a] += t.ai;
      model.nbr_w[t.b] += t.aj;
      model.nbr_w[t.c] += t.ak;
      if (std::abs(t.beta) > kBetaZeroRelative * size)
        model.beta.push_back(BetaTriplet{model.nbr[t.a], model.nbr[t.b], model.nbr[t.c], t.beta});
      ++m;
    }
    if (m == 0)
      throw CompileError(who(model, p) + ": neighbourhood is degenerate: all " + std::to_string(nn) +
                         " neighbours are collinear, no valid triplet");
    model.triplet_count[p] = m;
    const double inv_m = 1.0 / m;
    for (int a = s; a < e; ++a) model.nbr_w[a] *= inv_m;
    for (size_t t = first_beta; t < model.beta.size(); ++t) model.beta[t].b *= inv_m;
  }
  model.beta_start[n] = static_cast<int>(model.beta.size());
  build_triplet_chunks(model);  // the layout the shape-memory stage reads
}

}  // namespace ps
