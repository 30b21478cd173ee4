// Displacement measurements like the paper's Fig. 12: how far the particles of an organ moved
// between a reference state (e.g. settled before the bladder fills or the probe pushes) and now,
// as numbers (mean, max, mean vector; whole organ and per zone) and as a per-particle CSV that a
// viewer can colour. Zones split the organ into thirds by reference position along a superior
// direction: apex (inferior third), mid, base (superior third, next to the bladder).
// Called outside the step (they allocate).
#pragma once
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

struct ZoneStats {
  std::string name;                // "all", "apex", "mid", "base"
  int count = 0;                   // particles
  double mean = 0.0;               // mean |u| [m]
  double max = 0.0;                // max |u| [m]
  Vec3 mean_vec = Vec3::Zero();    // mean u (net motion of the zone) [m]
};

struct DisplacementStats {
  ZoneStats all;
  ZoneStats apex, mid, base;
};

// Zone of each particle of `component` (0 apex, 1 mid, 2 base) by its x_ref position along
// `superior` (unit) within the component's extent.
std::vector<int> si_zones(const Model& m, int component, const std::vector<Vec3>& x_ref, const Vec3& superior);

// u = x - x_ref over the particles of `component`.
DisplacementStats displacement_stats(const Model& m, int component, const std::vector<Vec3>& x_ref,
                                     const std::vector<Vec3>& x, const Vec3& superior);

// Header: id,component,zone,x0_mm,y0_mm,z0_mm,x_mm,y_mm,z_mm,ux_mm,uy_mm,uz_mm,u_mm. One row per
// particle of `component` (-1: every component; zones per component).
std::string displacement_csv(const Model& m, int component, const std::vector<Vec3>& x_ref, const std::vector<Vec3>& x,
                             const Vec3& superior);
// Written atomically (engine/util/atomic_file.h).
void write_displacement_csv(const std::string& path, const Model& m, int component, const std::vector<Vec3>& x_ref,
                            const std::vector<Vec3>& x, const Vec3& superior);

}  // namespace ps
