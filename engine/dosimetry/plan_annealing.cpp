#include "engine/dosimetry/plan_annealing.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace ps::dosimetry {

namespace {

constexpr uint8_t kProstateBit = 1, kUrethraBit = 2, kRectumBit = 4;  // organ_mask.h

// SplitMix64 (Steele, Lea and Flood 2014): a fixed, portable stream of 64-bit numbers.
struct SplitMix64 {
  uint64_t s;
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
  size_t below(size_t n) { return static_cast<size_t>(uniform() * static_cast<double>(n)); }
};

// Per voxel: w_under x max(0, Rx - D) + w1 x max(0, D - l1) + w2 x max(0, D - l2) [Gy-weighted].
struct VoxelCost {
  std::vector<float> wu, w1, l1, w2, l2;
};

VoxelCost voxel_costs(const PlanningMatrix& m, double rx, const AnnealWeights& w) {
  VoxelCost v;
  const size_t n = m.voxels;
  v.wu.assign(n, 0.0f);
  v.w1.assign(n, 0.0f);
  v.l1.assign(n, 1e30f);
  v.w2.assign(n, 0.0f);
  v.l2.assign(n, 1e30f);
  for (size_t q = 0; q < n; ++q) {
    const uint8_t k = m.kind[q];
    if (k & kProstateBit) {
      v.wu[q] = static_cast<float>(w.under);
      v.w1[q] = static_cast<float>(w.over);
      v.l1[q] = static_cast<float>(w.over_level * rx);
    }
    if (k & kUrethraBit) {
      v.w2[q] = static_cast<float>(w.urethra);
      v.l2[q] = static_cast<float>(w.urethra_level * rx);
    } else if (k & kRectumBit) {
      v.w2[q] = static_cast<float>(w.rectum);
      v.l2[q] = static_cast<float>(w.rectum_level * rx);
    }
  }
  return v;
}

class Search {
 public:
  Search(const PlanningMatrix& m, double rx, const AnnealWeights& w, std::vector<char> loaded)
      : m_(m), rx_(static_cast<float>(rx)), w_(w), vc_(voxel_costs(m, rx, w)), loaded_(std::move(loaded)) {
    loaded_.resize(m.candidates, 0);
    size_t np = 0;
    for (uint8_t k : m.kind) np += (k & kProstateBit) ? 1 : 0;
    norm_ = 1.0 / (rx * static_cast<double>(std::max<size_t>(1, np)));
    int holes = 0;
    for (int h : m.hole) holes = std::max(holes, h + 1);
    per_hole_.assign(static_cast<size_t>(holes), 0);
    std::map<std::tuple<int, int, int>, int> at;
    for (size_t c = 0; c < m.candidates; ++c) at[{m.col[c], m.row[c], m.step[c]}] = static_cast<int>(c);
    neighbours_.resize(m.candidates);
    for (size_t c = 0; c < m.candidates; ++c) {
      const int dc[6][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
      for (const auto& d : dc) {
        const auto it = at.find({m.col[c] + d[0], m.row[c] + d[1], m.step[c] + d[2]});
        if (it != at.end()) neighbours_[c].push_back(it->second);
      }
    }
    recompute();
  }

  void recompute() {
    D_.assign(m_.voxels, 0.0f);
    std::fill(per_hole_.begin(), per_hole_.end(), 0);
    for (size_t c = 0; c < m_.candidates; ++c)
      if (loaded_[c]) {
        const float* d = &m_.dose_gy[c * m_.voxels];
        for (size_t q = 0; q < m_.voxels; ++q) D_[q] += d[q];
        ++per_hole_[static_cast<size_t>(m_.hole[c])];
      }
  }

  double cost() const {
    double s = 0.0;
    for (size_t q = 0; q < m_.voxels; ++q) s += voxel(q, D_[q]);
    int holes = 0;
    for (int n : per_hole_) holes += n > 0;
    return s * norm_ + w_.needle * holes;
  }

  // cost change of adding `add` x dose of candidate a and `sub` x dose of candidate b (b may be -1)
  double delta(int a, float add, int b, float sub) const {
    const float* da = &m_.dose_gy[static_cast<size_t>(a) * m_.voxels];
    const float* db = b >= 0 ? &m_.dose_gy[static_cast<size_t>(b) * m_.voxels] : nullptr;
    double s = 0.0;
    for (size_t q = 0; q < m_.voxels; ++q) {
      const float D = D_[q];
      const float E = D + add * da[q] + (db ? sub * db[q] : 0.0f);
      s += voxel(q, E) - voxel(q, D);
    }
    double dn = 0.0;
    const size_t ha = static_cast<size_t>(m_.hole[static_cast<size_t>(a)]);
    if (b >= 0 && m_.hole[static_cast<size_t>(b)] == m_.hole[static_cast<size_t>(a)]) return s * norm_;
    if (add > 0 && per_hole_[ha] == 0) dn += w_.needle;
    if (add < 0 && per_hole_[ha] == 1) dn -= w_.needle;
    if (b >= 0) {
      const size_t hb = static_cast<size_t>(m_.hole[static_cast<size_t>(b)]);
      if (sub < 0 && per_hole_[hb] == 1) dn -= w_.needle;
    }
    return s * norm_ + dn;
  }

  void apply(int c, bool load) {
    const float sgn = load ? 1.0f : -1.0f;
    const float* d = &m_.dose_gy[static_cast<size_t>(c) * m_.voxels];
    for (size_t q = 0; q < m_.voxels; ++q) D_[q] += sgn * d[q];
    loaded_[static_cast<size_t>(c)] = load ? 1 : 0;
    per_hole_[static_cast<size_t>(m_.hole[static_cast<size_t>(c)])] += load ? 1 : -1;
  }

  // a proposed move: toggle a (b < 0), or move the seed at b to a
  struct Move {
    int a = -1, b = -1;
  };
  double move_delta(const Move& mv) const {
    if (mv.b < 0) return loaded_[static_cast<size_t>(mv.a)] ? delta(mv.a, -1.0f, -1, 0.0f) : delta(mv.a, 1.0f, -1, 0.0f);
    return delta(mv.a, 1.0f, mv.b, -1.0f);
  }
  void take(const Move& mv) {
    if (mv.b < 0) {
      apply(mv.a, !loaded_[static_cast<size_t>(mv.a)]);
    } else {
      apply(mv.b, false);
      apply(mv.a, true);
    }
  }

  bool propose(SplitMix64& rng, Move& mv) const {
    if (rng.uniform() < 0.5) {
      mv = {static_cast<int>(rng.below(m_.candidates)), -1};
      return true;
    }
    // a shift: a loaded seed to a free neighbouring site
    if (loaded_count() == 0) return false;
    const size_t start = rng.below(m_.candidates);
    for (size_t i = 0; i < m_.candidates; ++i) {
      const size_t c = (start + i) % m_.candidates;
      if (!loaded_[c]) continue;
      const auto& nb = neighbours_[c];
      if (nb.empty()) return false;
      const int to = nb[rng.below(nb.size())];
      if (loaded_[static_cast<size_t>(to)]) return false;
      mv = {to, static_cast<int>(c)};
      return true;
    }
    return false;
  }

  size_t loaded_count() const {
    size_t n = 0;
    for (char l : loaded_) n += l ? 1 : 0;
    return n;
  }

  // every toggle and shift in a fixed order: the best improving one; false when none improves
  bool descend_once() {
    Move best;
    double best_d = -1e-12;
    for (size_t c = 0; c < m_.candidates; ++c) {
      const Move mv{static_cast<int>(c), -1};
      const double d = move_delta(mv);
      if (d < best_d) { best_d = d; best = mv; }
    }
    for (size_t c = 0; c < m_.candidates; ++c) {
      if (!loaded_[c]) continue;
      for (int to : neighbours_[c]) {
        if (loaded_[static_cast<size_t>(to)]) continue;
        const Move mv{to, static_cast<int>(c)};
        const double d = move_delta(mv);
        if (d < best_d) { best_d = d; best = mv; }
      }
    }
    if (best.a < 0) return false;
    take(best);
    return true;
  }

  const std::vector<char>& loaded() const { return loaded_; }

 private:
  double voxel(size_t q, float D) const {
    return vc_.wu[q] * std::max(0.0f, rx_ - D) + vc_.w1[q] * std::max(0.0f, D - vc_.l1[q]) +
           vc_.w2[q] * std::max(0.0f, D - vc_.l2[q]);
  }
  const PlanningMatrix& m_;
  float rx_;
  AnnealWeights w_;
  VoxelCost vc_;
  std::vector<char> loaded_;
  std::vector<float> D_;
  std::vector<int> per_hole_;
  std::vector<std::vector<int>> neighbours_;
  double norm_ = 1.0;
};

}  // namespace

double loading_cost(const PlanningMatrix& m, double rx, const AnnealWeights& w, const std::vector<char>& loaded) {
  return Search(m, rx, w, loaded).cost();
}

AnnealResult anneal_loading(const PlanningMatrix& m, double rx, const AnnealWeights& w, std::vector<char> start,
                            uint64_t seed, long iterations) {
  AnnealResult r;
  if (m.candidates == 0) return r;
  Search s(m, rx, w, std::move(start));
  SplitMix64 rng{seed};
  // the starting temperature: the mean |cost change| of the first moves proposed
  double t0 = 0.0;
  int sampled = 0;
  for (int i = 0; i < 4096 && sampled < 256; ++i) {
    Search::Move mv;
    if (!s.propose(rng, mv)) continue;
    t0 += std::abs(s.move_delta(mv));
    ++sampled;
  }
  t0 = sampled > 0 ? t0 / sampled : 1e-3;
  const double t1 = 1e-3 * t0;
  const double cool = iterations > 1 ? std::pow(t1 / t0, 1.0 / static_cast<double>(iterations - 1)) : 1.0;
  double T = t0;
  for (long it = 0; it < iterations; ++it, T *= cool) {
    Search::Move mv;
    if (!s.propose(rng, mv)) continue;
    ++r.moves_tried;
    const double d = s.move_delta(mv);
    if (d <= 0.0 || rng.uniform() < std::exp(-d / T)) {
      s.take(mv);
      if (++r.moves_taken % 4096 == 0) s.recompute();  // no float drift from many additions
    }
  }
  s.recompute();
  while (s.descend_once()) ++r.moves_taken;
  s.recompute();
  r.loaded = s.loaded();
  r.cost = s.cost();
  return r;
}

}  // namespace ps::dosimetry
