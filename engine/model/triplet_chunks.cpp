#include "engine/model/triplet_chunks.h"

#include <algorithm>
#include <array>
#include <map>
#include <string>

#include "engine/util/error.h"

namespace ps {

namespace {

struct Half { std::array<int, 3> abc; double beta[2]; };

// The beta triplets of particle p as neighbour slots, in Model::beta order.
std::vector<std::array<int, 3>> slot_triplets(const Model& m, int p) {
  const int ns = m.nbr_start[p], nn = m.nbr_start[p + 1] - ns;
  auto slot = [&](int q) {
    for (int s = 0; s < nn; ++s)
      if (m.nbr[ns + s] == q) return s;
    throw CompileError("particle " + std::to_string(p) + ": beta triplet vertex " + std::to_string(q) +
                       " is not one of its neighbours");
  };
  std::vector<std::array<int, 3>> out;
  for (int t = m.beta_start[p]; t < m.beta_start[p + 1]; ++t)
    out.push_back({slot(m.beta[t].i), slot(m.beta[t].j), slot(m.beta[t].k)});
  return out;
}

std::array<int, 3> rotated(const std::array<int, 3>& t, int r) {  // cyclic: the same normal
  return {t[r % 3], t[(r + 1) % 3], t[(r + 2) % 3]};
}

// Greedy pairing of the particle's triplets into half-chunks, in triplet order.
std::vector<Half> halves_of(const std::vector<std::array<int, 3>>& ts, const double* beta) {
  std::map<std::array<int, 3>, std::vector<int>> by_key;  // rotated vertices -> triplets
  for (size_t t = 0; t < ts.size(); ++t)
    for (int r = 0; r < 3; ++r) by_key[rotated(ts[t], r)].push_back(static_cast<int>(t));
  std::vector<char> used(ts.size(), 0);
  auto take = [&](std::array<int, 3> key, int self) {
    auto it = by_key.find(key);
    if (it == by_key.end()) return -1;
    for (int u : it->second)
      if (!used[u] && u != self) return u;
    return -1;
  };
  std::vector<Half> out;
  for (size_t t = 0; t < ts.size(); ++t) {
    if (used[t]) continue;
    used[t] = 1;
    bool paired = false;
    for (int r = 0; r < 3 && !paired; ++r) {
      const std::array<int, 3> k = rotated(ts[t], r);
      if (const int u = take({k[0], k[1], k[2] + 1}, static_cast<int>(t)); u >= 0) {
        used[u] = 1;
        out.push_back({k, {beta[t], beta[u]}});
        paired = true;
      } else if (const int v = k[2] > 0 ? take({k[0], k[1], k[2] - 1}, static_cast<int>(t)) : -1; v >= 0) {
        used[v] = 1;
        out.push_back({{k[0], k[1], k[2] - 1}, {beta[v], beta[t]}});
        paired = true;
      }
    }
    if (!paired) out.push_back({ts[t], {beta[t], 0.0}});  // lane c + 1 reads the padding slot at most
  }
  return out;
}

}  // namespace

void build_triplet_chunks(Model& m) {
  const int n = m.particle_count();
  m.chunk_start.assign(n + 1, 0);
  m.chunks.clear();
  m.chunk_beta.clear();
  m.most_chunks = 0;
  for (int p = 0; p < n; ++p) {
    m.chunk_start[p] = static_cast<int>(m.chunks.size());
    if (m.beta_start[p + 1] == m.beta_start[p]) continue;
    std::vector<double> beta;
    for (int t = m.beta_start[p]; t < m.beta_start[p + 1]; ++t) beta.push_back(m.beta[t].b);
    std::vector<Half> hs = halves_of(slot_triplets(m, p), beta.data());
    if (hs.size() % 2) hs.push_back({hs.back().abc, {0.0, 0.0}});  // a half that adds zero
    for (size_t h = 0; h < hs.size(); h += 2) {
      TripletChunk c;
      for (int k = 0; k < 2; ++k) {
        c.a[k] = static_cast<uint8_t>(hs[h + k].abc[0]);
        c.b[k] = static_cast<uint8_t>(hs[h + k].abc[1]);
        c.c[k] = static_cast<uint8_t>(hs[h + k].abc[2]);
        c.a4[k] = static_cast<uint8_t>(4 * c.a[k]);
        c.b4[k] = static_cast<uint8_t>(4 * c.b[k]);
        c.c4[k] = static_cast<uint8_t>(4 * c.c[k]);
        m.chunk_beta.push_back(hs[h + k].beta[0]);
        m.chunk_beta.push_back(hs[h + k].beta[1]);
      }
      m.chunks.push_back(c);
    }
    m.most_chunks = std::max(m.most_chunks, static_cast<int>(hs.size() / 2));
  }
  m.chunk_start[n] = static_cast<int>(m.chunks.size());
}

}  // namespace ps
