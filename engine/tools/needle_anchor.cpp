#include "engine/tools/needle_anchor.h"

#include <algorithm>
#include <cmath>

#include "engine/model/discrete_coordinates.h"

namespace ps {

void AffineAnchor::build(const Vec3& X, const int* ids, int n, const std::vector<Vec3>& x, const Vec3& keep) {
  reset();
  n = std::min(n, kAnchorMaxNeighbours);
  if (n <= 0) return;
  count = n;
  for (int a = 0; a < n; ++a) { idx[a] = ids[a]; w[a] = 0.0; }
  double size = 0.0;
  for (int a = 0; a < n; ++a) size = std::max(size, (x[idx[a]] - X).norm());
  int m = 0;
  // same triplet construction and rejection rule as the model's particles (compile time)
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c = b + 1; c < n; ++c) {
        const Vec3& Ni = x[idx[a]];
        const Vec3& Nj = x[idx[b]];
        const Vec3& Nk = x[idx[c]];
        const Vec3 eij = Nj - Ni, eik = Nk - Ni, ejk = Nk - Nj;
        const Vec3 nrm = eij.cross(eik);
        const double longest2 = std::max({eij.squaredNorm(), eik.squaredNorm(), ejk.squaredNorm()});
        if (!(nrm.norm() >= kTripletQualityMin * longest2) || !(longest2 > 0.0)) continue;
        const double area2 = nrm.squaredNorm();
        const Vec3 nhat = nrm / std::sqrt(area2);
        const double bt = (X - Ni).dot(nhat);
        const Vec3 Q = X - bt * nhat;
        const double aj = (Q - Ni).cross(eik).dot(nrm) / area2;
        const double ak = eij.cross(Q - Ni).dot(nrm) / area2;
        w[a] += 1.0 - aj - ak;
        w[b] += aj;
        w[c] += ak;
        if (std::abs(bt) > kBetaZeroRelative * size) beta[nbeta++] = AnchorTriplet{idx[a], idx[b], idx[c], bt};
        ++m;
      }
  // Extrapolating coordinates (X beside its particles, not among them: the nodes near a hole in a
  // wall, held by 3-4 wall particles on one side) had weights up to 6.3 and -2.8; the spring's
  // reaction was multiplied on single light particles and the wall chattered at 1-5 m/s
  // (docs/robustness.md, "The rectal wall at the hole"). Such an anchor takes the translation form.
  bool extrapolates = false;
  if (m > 0) {
    const double inv_m = 1.0 / m;
    for (int a = 0; a < n; ++a) {
      w[a] *= inv_m;
      extrapolates |= w[a] < -kAnchorWeightMargin || w[a] > 1.0 + kAnchorWeightMargin;
    }
    for (int t = 0; t < nbeta; ++t) beta[t].b *= inv_m;
  }
  if (m > 0 && !extrapolates) {
    rotational = true;
  } else {
    // translation-only fallback: normalised inverse distances (a particle on X takes it all)
    rotational = false;
    nbeta = 0;
    double sum = 0.0;
    int on_point = -1;
    for (int a = 0; a < n; ++a) {
      const double d = (x[idx[a]] - X).norm();
      if (!(d > 1e-12)) { on_point = a; break; }
      w[a] = 1.0 / d;
      sum += w[a];
    }
    for (int a = 0; a < n; ++a) w[a] = on_point >= 0 ? (a == on_point ? 1.0 : 0.0) : w[a] / sum;
  }
  offset.setZero();
  offset = keep - evaluate(x);
}

Vec3 AffineAnchor::evaluate(const std::vector<Vec3>& x) const {
  Vec3 p = offset;
  for (int a = 0; a < count; ++a) p += w[a] * x[idx[a]];
  for (int t = 0; t < nbeta; ++t) {
    const AnchorTriplet& bt = beta[t];
    const Vec3 nrm = (x[bt.j] - x[bt.i]).cross(x[bt.k] - x[bt.i]);
    const double len2 = nrm.squaredNorm();
    if (len2 > 0.0) p += (bt.b / std::sqrt(len2)) * nrm;
  }
  return p;
}

void AffineAnchor::add_reaction(std::vector<Vec3>& f, const std::vector<Vec3>& x, const Vec3& F) const {
  for (int a = 0; a < count; ++a) f[idx[a]] -= w[a] * F;
  // d(b n/|n|)/dx_q transposed applied to F (engine/step/shape_memory.cpp, same algebra)
  for (int t = 0; t < nbeta; ++t) {
    const AnchorTriplet& bt = beta[t];
    const Vec3 ej = x[bt.j] - x[bt.i], ek = x[bt.k] - x[bt.i];
    const Vec3 nrm = ej.cross(ek);
    const double len2 = nrm.squaredNorm();
    if (!(len2 > 0.0)) continue;
    const double inv_len = 1.0 / std::sqrt(len2);
    const Vec3 Fp = (bt.b * inv_len) * (F - (nrm.dot(F) / len2) * nrm);
    const Vec3 fj = ek.cross(Fp), fk = ej.cross(Fp);
    f[bt.j] -= fj;
    f[bt.k] += fk;
    f[bt.i] += fj - fk;
  }
}

Vec3 AffineAnchor::velocity(const std::vector<Vec3>& v) const {
  Vec3 u = Vec3::Zero();
  for (int a = 0; a < count; ++a) u += w[a] * v[idx[a]];
  return u;
}

}  // namespace ps
