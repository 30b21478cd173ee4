// The chunk layout the shape-memory stage reads (engine/model/triplet_chunks.h) holds every beta
// triplet exactly once, with its b, as a cyclic rotation of its vertices (the same normal), and
// nothing else: every other lane has b = 0.
#include "engine/model/triplet_chunks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

// the triplet's vertices as a canonical rotation (smallest index first), with its b
using Key = std::array<int, 3>;
Key canonical(int i, int j, int k) {
  if (i < j && i < k) return {i, j, k};
  if (j < i && j < k) return {j, k, i};
  return {k, i, j};
}

void expect_layout_holds_every_triplet_once(const Model& m) {
  const int n = m.particle_count();
  ASSERT_EQ(m.chunk_start.size(), static_cast<size_t>(n + 1));
  ASSERT_EQ(m.chunk_beta.size(), 4 * m.chunks.size());
  size_t real_lanes = 0;
  for (int p = 0; p < n; ++p) {
    std::map<Key, double> want;  // rotation-free triplets of p and their b
    for (int t = m.beta_start[p]; t < m.beta_start[p + 1]; ++t)
      want[canonical(m.beta[t].i, m.beta[t].j, m.beta[t].k)] = m.beta[t].b;
    const int ns = m.nbr_start[p], nn = m.nbr_start[p + 1] - ns;
    EXPECT_LE(m.chunk_start[p + 1] - m.chunk_start[p], m.most_chunks);
    for (int c = m.chunk_start[p]; c < m.chunk_start[p + 1]; ++c) {
      const TripletChunk& ch = m.chunks[c];
      for (int h = 0; h < 2; ++h) {
        EXPECT_EQ(ch.a4[h], 4 * ch.a[h]);
        EXPECT_EQ(ch.b4[h], 4 * ch.b[h]);
        EXPECT_EQ(ch.c4[h], 4 * ch.c[h]);
        for (int l = 0; l < 2; ++l) {
          const double b = m.chunk_beta[4 * c + 2 * h + l];
          if (b == 0.0) continue;  // a padding lane: adds exactly zero
          const int sa = ch.a[h], sb = ch.b[h], sc = ch.c[h] + l;
          ASSERT_LT(std::max({sa, sb, sc}), nn) << "particle " << p;
          const Key k = canonical(m.nbr[ns + sa], m.nbr[ns + sb], m.nbr[ns + sc]);
          auto it = want.find(k);
          ASSERT_NE(it, want.end()) << "particle " << p << ": a lane holds no beta triplet of it (or one twice)";
          EXPECT_EQ(it->second, b) << "particle " << p;
          want.erase(it);
          ++real_lanes;
        }
      }
    }
    EXPECT_TRUE(want.empty()) << "particle " << p << ": " << want.size() << " beta triplets missing";
  }
  EXPECT_EQ(real_lanes, m.beta.size());
}

TEST(TripletChunks, HoldEveryBetaTripletOnceOnALattice) {
  auto m = test::compile_text(test::cube_yaml(40, 10));
  expect_layout_holds_every_triplet_once(*m);
  // the 8 octant triplets of an interior lattice particle pair up into exactly 2 full chunks
  int interior = 0;
  for (int p = 0; p < m->particle_count(); ++p)
    if (m->beta_start[p + 1] - m->beta_start[p] == 8) {
      ++interior;
      EXPECT_EQ(m->chunk_start[p + 1] - m->chunk_start[p], 2) << "particle " << p;
    }
  EXPECT_EQ(interior, 27);  // 3 x 3 x 3 inside a 5 x 5 x 5 lattice
}

TEST(TripletChunks, HoldEveryBetaTripletOnceOnAMeshBody) {
  auto m = test::compile_text(
      "name: cyl\nmaterials: {soft: {young_kpa: 60}}\ncomponents:\n"
      "  - {name: c, material: soft, spacing_mm: 6, cylinder: {radius_mm: 19, length_mm: 60, axis: [0.2, 0.3, 1]}}\n");
  expect_layout_holds_every_triplet_once(*m);
}

}  // namespace
}  // namespace ps
