// A regular dose grid (voxel centres, millimetres) and the live dose on it: each seed's total dose
// is added from a precomputed along-away kernel of its model (bilinear, 0.25 mm), and when a seed
// moves with the tissue (more than a tolerance) its old contribution is taken away and the new one
// added, so an update after a seed drops costs one seed's pass over the grid, not all of them.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/dosimetry/seed.h"

namespace ps::dosimetry {

struct GridSpec {
  Vec3 origin_mm = Vec3::Zero();    // centre of voxel (0, 0, 0)
  double spacing_mm = 1.0;
  int nx = 0, ny = 0, nz = 0;
  size_t size() const { return static_cast<size_t>(nx) * ny * nz; }
  size_t index(int i, int j, int k) const { return (static_cast<size_t>(k) * ny + j) * nx + i; }
  Vec3 centre_mm(int i, int j, int k) const { return origin_mm + spacing_mm * Vec3(i, j, k); }
  double voxel_cc() const { return spacing_mm * spacing_mm * spacing_mm * 1e-3; }
};

// The grid covering the box [lo, hi] grown by margin on every side.
GridSpec grid_around(const Vec3& lo_mm, const Vec3& hi_mm, double margin_mm, double spacing_mm);

// Total dose per unit strength of one seed as a function of (|along|, away) [Gy/U], tabulated.
class DoseKernel {
 public:
  explicit DoseKernel(const SourceModel& s, double extent_mm = 128.0, double step_mm = 0.25);
  double gy_per_u(double along_abs_mm, double away_mm) const;
  const SourceModel& model() const { return *model_; }

 private:
  const SourceModel* model_;
  double step_mm_, inv_step_;
  int n_;
  std::vector<float> k_;            // [ia * n + ir]
};

class DoseAccumulator {
 public:
  DoseAccumulator(const SourceModel& s, const GridSpec& g);
  // Brings the grid to the dose of `seeds` (seeds keep their index: new ones are appended): adds
  // new seeds, re-adds those whose centre moved more than move_tol_mm or whose axis turned more
  // than ~3 deg, removes those no longer in the list. Returns how many seed passes it made. At
  // most max_moved moved seeds are re-added per call (new and removed seeds always are): the rest
  // keep their last position until a later call, so one call's cost stays bounded while the
  // tissue carries every seed a little.
  int update(const std::vector<Seed>& seeds, double move_tol_mm = 0.25, int max_moved = 1 << 30);
  // Seeds whose applied position lags their position in the last update (budget exhausted).
  int lagging() const { return lagging_; }
  // Recomputes from zero (no drift from the additions and removals).
  void rebuild(const std::vector<Seed>& seeds);
  const GridSpec& spec() const { return spec_; }
  const std::vector<float>& dose_gy() const { return dose_; }
  const SourceModel& model() const { return kernel_.model(); }
  size_t seeds_applied() const { return applied_.size(); }

 private:
  void add(const Seed& s, float sign);
  GridSpec spec_;
  DoseKernel kernel_;
  std::vector<float> dose_;
  std::vector<Seed> applied_;
  int lagging_ = 0;
};

}  // namespace ps::dosimetry
