// The seed-selection search of the implant plan (engine/dosimetry/plan.h): which candidate seed
// sites (points at 5 mm steps on the template lines, each with its dose per voxel of a planning
// grid) to load, found by simulated annealing over that dose matrix (after Pouliot et al., "Optimization
// of permanent 125I prostate implants using fast simulated annealing", Int J Radiat Oncol Biol
// Phys 36:711, 1996; linear dose-volume penalties as in IPSA, Lessard and Pouliot, Med Phys
// 28:773, 2001), then a deterministic descent to a local minimum.
//
// Cost of a loading (each term per voxel, in units of the prescription Rx, summed and divided by
// the number of prostate voxels; D the voxel's total dose):
//   prostate  w_under x max(0, Rx - D) + w_over x max(0, D - over_level x Rx)
//   urethra   w_urethra x max(0, D - urethra_level x Rx)
//   rectum    w_rectum x max(0, D - rectum_level x Rx)
// plus w_needle for each template hole that carries at least one seed (fewer needles).
// Moves: load or unload one candidate (uniform over all), or shift a loaded seed to a free
// neighbouring site (one step along its line, or the same depth in a neighbouring hole). A move
// of cost change dC is taken when dC <= 0, or with probability exp(-dC / T); T falls
// geometrically from T0 (the mean |dC| of the first 256 moves proposed from the start) to
// T0 / 1000 over the iterations. The random numbers come from a fixed-seed SplitMix64 stream:
// the same input gives the same plan on every machine with the same floating point.
// After the annealing, every single load, unload and shift is tried in a fixed order and the best
// improving one taken until none improves the cost.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ps::dosimetry {

struct PlanningMatrix {
  size_t candidates = 0, voxels = 0;
  std::vector<float> dose_gy;       // [c * voxels + q]: one seed at candidate c, at voxel q [Gy]
  std::vector<uint8_t> kind;        // [voxels] structure bits (organ_mask.h: kProstate, kUrethra, kRectum)
  std::vector<int> hole;            // [candidates] template hole index
  std::vector<int> col, row, step;  // [candidates] hole column, row; step along the line (depth / step)
};

struct AnnealWeights {
  double under = 1.0;               // prostate below Rx
  double over = 0.08, over_level = 1.5;       // prostate above over_level x Rx
  double urethra = 8.0, urethra_level = 1.25;  // urethra above urethra_level x Rx
  double rectum = 8.0, rectum_level = 0.7;     // rectum above rectum_level x Rx
  double needle = 0.002;            // per loaded hole
};

struct AnnealResult {
  std::vector<char> loaded;         // [candidates]
  double cost = 0.0;
  long moves_tried = 0, moves_taken = 0;
};

// Starts from `start` (empty: no seed loaded). iterations: annealing moves proposed.
AnnealResult anneal_loading(const PlanningMatrix& m, double rx_gy, const AnnealWeights& w, std::vector<char> start,
                            uint64_t seed, long iterations);

// The cost of a loading (for tests and reports).
double loading_cost(const PlanningMatrix& m, double rx_gy, const AnnealWeights& w, const std::vector<char>& loaded);

}  // namespace ps::dosimetry
