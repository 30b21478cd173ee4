// The seed implant's dose as a view of a published Snapshot shows it (issue 46), for the trainee
// window's dose worker (app/gui/dose_worker.h) and the replay frames: the deposited seeds from the
// snapshot's DrawList (capsules of role Seed, each along its needle), the organs from its particle
// positions (prostate and rectum surfaces, the urethra's centre line carried by the tissue), the
// dose grid over the gland (1 mm, 10 mm margin) brought up to date incrementally
// (engine/dosimetry/live_dosimetry.h), its indices and DVH, and a copy of the grid for isodose
// lines and surfaces. Reader side: allocates; never on the physics thread.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "engine/contract/snapshot.h"
#include "engine/dosimetry/isodose.h"
#include "engine/dosimetry/live_dosimetry.h"
#include "engine/metrics/tracked_point.h"

namespace ps {
struct Scene;
}

namespace ps::frames {

class SnapshotDose {
 public:
  // Whether any needle of the scene carries seeds (the dose views are shown only then).
  static bool scene_has_seeds(const Scene& scene);
  // Throws InputError for an unknown isotope or a scene without a gland surface.
  explicit SnapshotDose(const Scene& scene, const std::string& isotope = "I125_6711", double prescription_gy = 145.0,
                        double strength_u = 0.5);

  // The deposited seeds of a snapshot [mm], `out` cleared first.
  void seeds_of(const Snapshot& snap, std::vector<dosimetry::Seed>& out) const;
  // The dose of `seeds` on the organs at positions x (flat xyz [m], as Snapshot::x).
  const dosimetry::LiveDosimetry::Result& update(const std::vector<float>& x, const std::vector<dosimetry::Seed>& seeds);
  const dosimetry::LiveDosimetry::Result& update(const Snapshot& snap);
  // A copy of the grid as it is now.
  std::shared_ptr<const dosimetry::DoseField> field() const;
  double prescription_gy() const { return live_->prescription_gy(); }
  const dosimetry::LiveDosimetry& live() const { return *live_; }

 private:
  const Model* model_;
  double strength_u_;
  std::vector<int> prostate_ids_, rectum_ids_;   // surface particles, in the faces' local order
  std::vector<TrackedPoint> urethra_;
  std::unique_ptr<dosimetry::LiveDosimetry> live_;
  std::vector<Vec3> pv_, rv_, uv_, x_;
  std::vector<dosimetry::Seed> seeds_;
};

}  // namespace ps::frames
