// The seed-selection search (engine/dosimetry/plan_annealing.h) on small dose matrices whose best
// loading is known: it loads what covers the prostate, leaves out a site that would overdose the
// urethra when another covers the same voxels, gives the same loading for the same seed, and its
// cost is what loading_cost() says.
#include "engine/dosimetry/plan_annealing.h"

#include <gtest/gtest.h>

namespace ps::dosimetry {
namespace {

constexpr uint8_t kP = 1, kU = 2;

// candidates on one line (hole 0, steps 0..n-1); each covers its own prostate voxels
PlanningMatrix line_problem(int n, int voxels_each) {
  PlanningMatrix m;
  m.candidates = static_cast<size_t>(n);
  m.voxels = static_cast<size_t>(n * voxels_each);
  m.kind.assign(m.voxels, kP);
  m.dose_gy.assign(m.candidates * m.voxels, 0.0f);
  for (int c = 0; c < n; ++c) {
    m.hole.push_back(0);
    m.col.push_back(0);
    m.row.push_back(0);
    m.step.push_back(c);
    for (int q = 0; q < voxels_each; ++q) m.dose_gy[static_cast<size_t>(c) * m.voxels + c * voxels_each + q] = 150.0f;
  }
  return m;
}

TEST(PlanAnnealing, LoadsEverySiteThatCoversItsOwnVoxels) {
  const PlanningMatrix m = line_problem(12, 5);
  const AnnealResult r = anneal_loading(m, 145.0, AnnealWeights{}, {}, 7, 20000);
  ASSERT_EQ(r.loaded.size(), 12u);
  for (char l : r.loaded) EXPECT_TRUE(l);
  EXPECT_NEAR(r.cost, AnnealWeights{}.needle, 1e-9) << "no underdose left, one needle";
  EXPECT_NEAR(r.cost, loading_cost(m, 145.0, AnnealWeights{}, r.loaded), 1e-9);
}

TEST(PlanAnnealing, LeavesOutTheSiteThatOverdosesTheUrethraWhenAnotherCoversTheSame) {
  // two sites cover the same 10 prostate voxels; site 1 also puts 250 Gy on 3 urethra voxels
  PlanningMatrix m;
  m.candidates = 2;
  m.voxels = 13;
  m.kind.assign(10, kP);
  m.kind.insert(m.kind.end(), 3, kU);
  m.dose_gy.assign(2 * 13, 0.0f);
  for (int q = 0; q < 10; ++q) m.dose_gy[q] = m.dose_gy[13 + q] = 150.0f;
  for (int q = 10; q < 13; ++q) m.dose_gy[13 + q] = 250.0f;
  m.hole = {0, 1};
  m.col = {0, 1};
  m.row = {0, 0};
  m.step = {0, 0};
  const AnnealResult r = anneal_loading(m, 145.0, AnnealWeights{}, {0, 1}, 3, 5000);
  EXPECT_TRUE(r.loaded[0]);
  EXPECT_FALSE(r.loaded[1]) << "the urethra's overdose costs more than nothing gains";
}

TEST(PlanAnnealing, TheSameSeedGivesTheSameLoading) {
  // overlapping coverage: many loadings are near the optimum, so the stream decides between them
  PlanningMatrix m = line_problem(40, 3);
  for (size_t c = 0; c + 1 < m.candidates; ++c)
    for (int q = 0; q < 3; ++q) m.dose_gy[c * m.voxels + (c + 1) * 3 + q] = 90.0f;  // half onto the next site's voxels
  const AnnealResult a = anneal_loading(m, 145.0, AnnealWeights{}, {}, 11, 30000);
  const AnnealResult b = anneal_loading(m, 145.0, AnnealWeights{}, {}, 11, 30000);
  EXPECT_EQ(a.loaded, b.loaded);
  EXPECT_EQ(a.cost, b.cost);
  EXPECT_EQ(a.moves_taken, b.moves_taken);
  // no single load, unload or shift improves the result (the final descent)
  const double c0 = loading_cost(m, 145.0, AnnealWeights{}, a.loaded);
  for (size_t c = 0; c < m.candidates; ++c) {
    std::vector<char> t = a.loaded;
    t[c] = !t[c];
    EXPECT_GE(loading_cost(m, 145.0, AnnealWeights{}, t), c0 - 1e-9) << "toggle " << c;
  }
}

}  // namespace
}  // namespace ps::dosimetry
