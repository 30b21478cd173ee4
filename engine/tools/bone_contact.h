// Rigid bone (pubic arch, pelvis) as an obstacle for needle tips, through FCL: one bounding-volume
// hierarchy (OBBRSS) per rigid component's surface, in the body frame, queried at the body's
// current pose. A cheap bounding-box test comes first, so a tip far from bone costs a few
// comparisons and FCL is only asked when it is close.
#pragma once
#include <limits>
#include <memory>
#include <vector>

#include "engine/model/model.h"
#include "engine/state/state.h"

namespace ps {

class BoneContact {
 public:
  explicit BoneContact(const Model& m);   // every rigid component with a surface
  ~BoneContact();
  BoneContact(const BoneContact&) = delete;
  BoneContact& operator=(const BoneContact&) = delete;

  bool empty() const;
  int bone_count() const;
  // Distance [m] from a sphere (centre c, radius r) to the nearest bone surface among bones whose
  // box comes within `reach` of c; +inf when none does. 0 when touching or overlapping.
  // `nearest`: the closest point on that bone; `component`: its Model component.
  double distance(const State& s, const Vec3& c, double r, double reach, Vec3* nearest, int* component) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ps
