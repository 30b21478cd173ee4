// The implant's dose as the seeds drop, for the trainee window's dose worker (off the physics
// thread): the dose grid brought up to date incrementally (dose_grid.h: one seed pass per new or
// moved seed), the structure masks rebuilt on the organs where they are now, the indices and the
// cumulative DVH; the dose at any point (trilinear on the grid) and a copy of the grid for isodose
// lines and surfaces (isodose.h).
#pragma once
#include <array>
#include <vector>

#include <memory>

#include "engine/dosimetry/dvh.h"
#include "engine/dosimetry/isodose.h"

namespace ps::dosimetry {

class LiveDosimetry {
 public:
  LiveDosimetry(const SourceModel& s, const GridSpec& g, std::vector<std::array<int, 3>> prostate_faces,
                std::vector<std::array<int, 3>> rectum_faces, double prescription_gy, double urethra_radius_mm = 3.0);

  struct Result {
    DosimetryIndices indices;
    DvhCurve dvh;
    int seed_passes = 0;            // seeds added, moved or removed in this update
  };
  // Seeds where they are now; organ surface vertices (faces as given at construction) and the
  // urethra's centre line where they are now [mm].
  const Result& update(const std::vector<Seed>& seeds, const std::vector<Vec3>& prostate_mm,
                       const std::vector<Vec3>& rectum_mm, const std::vector<Vec3>& urethra_mm);
  const Result& result() const { return result_; }
  // Dose at p [Gy], trilinear between voxel centres; 0 outside the grid.
  double dose_at(const Vec3& p_mm) const;
  // A copy of the grid and its dose as they are now (for isodose lines and surfaces elsewhere).
  std::shared_ptr<const DoseField> field() const;
  const GridSpec& spec() const { return acc_.spec(); }
  double prescription_gy() const { return rx_; }

 private:
  DoseAccumulator acc_;
  std::vector<std::array<int, 3>> prostate_faces_, rectum_faces_;
  double rx_, urethra_radius_mm_;
  std::vector<uint8_t> mask_;
  Result result_;
};

}  // namespace ps::dosimetry
