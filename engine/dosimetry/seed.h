// A seed in the tissue: centre, axis (along its needle track) and air-kerma strength; the total
// dose it delivers at a point (permanent implant, TG-43U1 2-D formalism, engine/dosimetry/tg43.h).
#pragma once
#include <vector>

#include "engine/dosimetry/source_models.h"
#include "engine/util/vec.h"

namespace ps::dosimetry {

struct Seed {
  Vec3 centre_mm = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();        // unit
  double strength_u = 0.0;          // air-kerma strength S_K [U = uGy m^2 h^-1]
};

// Total dose of one seed at point p [Gy].
double seed_total_dose_gy(const SourceModel& s, const Seed& seed, const Vec3& p_mm);
// Sum over the seeds [Gy].
double total_dose_gy(const SourceModel& s, const std::vector<Seed>& seeds, const Vec3& p_mm);

}  // namespace ps::dosimetry
