// From physical material parameters to the model's per-particle shape-memory stiffness.
//
// The shape-memory force of a particle is k_e (P* - P) with P* an affine combination of its
// neighbours. For a lattice of spacing h, a strain epsilon moves P* - P by O(epsilon h), the
// force on a particle face of area h^2 gives a stress O(k_e epsilon / h): so k_e ~ E h. The
// dimensionless factor is calibrated (docs/calibration.md) so that the hanging truth cylinder
// and its convergence study come out right; see `prostatesim validate`.
#pragma once

namespace ps {

// k_e = kShapeMemoryPerModulus * E * h   [N/m] = [-] * [Pa] * [m]
inline constexpr double kShapeMemoryPerModulus = 80.0;

inline double shape_memory_stiffness(double young_pa, double spacing_m) {
  return kShapeMemoryPerModulus * young_pa * spacing_m;
}

}  // namespace ps
