// Checks of the TG-43U1 implementation against published numbers it does not read: for I-125
// model 6711 the along-away dose-rate table (single seed, D'/S_K at points in Cartesian
// coordinates between the nodes of the polar g_L and F tables, to 7 cm) and the consensus 1-D
// anisotropy factor phi_an(r), which integrates the 2-D data over the sphere (so it tests the
// geometry function and the theta interpolation). `prostatesim validate tg43` prints them.
#pragma once
#include <string>
#include <vector>

namespace ps::dosimetry {

struct Tg43Comparison {
  std::string metric;
  double value = 0.0, reference = 0.0;
  double tolerance_rel = 0.02;      // |value / reference - 1| allowed
  double along_cm = 0.0, away_cm = 0.0;
};

// One row per along-away point with 0.5 cm <= r <= 7 cm.
std::vector<Tg43Comparison> check_6711_along_away();
// One row per consensus radius (0.5 .. 5 cm): phi_an from the implementation's dose rate.
std::vector<Tg43Comparison> check_6711_phi_an();

}  // namespace ps::dosimetry
