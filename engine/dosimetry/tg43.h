// AAPM TG-43U1 2-D line-source formalism (Rivard et al., Med. Phys. 31(3), 2004, eq. 1 and 11):
//   D'(r, theta) = S_K Lambda [G_L(r, theta) / G_L(r0, theta0)] g_L(r) F(r, theta),
//   r0 = 1 cm, theta0 = 90 deg, G_L = beta / (L r sin theta) (theta = 0: 1 / (r^2 - L^2 / 4)).
// Permanent implant: D = D'(t = 0) T_1/2 / ln 2 (complete decay).
// Interpolation and extrapolation, as TG-43U1 recommends where it says:
//  * g_L: linear between nodes; below the first node its value; beyond the last, log-linear on the
//    last two nodes;
//  * F: bilinear in (r, theta); below the first radius its values; beyond the last radius linear
//    on the last two radii (this reproduces the published 6711 along-away dose rates to 0.4 % up
//    to 7 cm along the axis, where holding the last radius is 10 % low: docs/dosimetry.md);
//  * r below r_min = 1 mm is held at 1 mm (the tables start there; inside a voxel of a seed).
#pragma once
#include "engine/dosimetry/source_models.h"

namespace ps::dosimetry {

inline constexpr double kMinRadiusCm = 0.1;

// Line-source geometry function G_L(r, theta) [cm^-2]; theta in radians, folded to [0, pi/2].
double geometry_function(double r_cm, double theta_rad, double length_cm);
double radial_dose(const SourceModel& s, double r_cm);
double anisotropy(const SourceModel& s, double r_cm, double theta_deg);
// Dose rate per unit air-kerma strength at (r, theta) [cGy h^-1 U^-1].
double dose_rate_per_u(const SourceModel& s, double r_cm, double theta_rad);
// Total dose of a permanent implant per unit dose rate [Gy per (cGy/h)]: T_1/2 [h] / ln 2 / 100.
double permanent_dose_factor(const SourceModel& s);

}  // namespace ps::dosimetry
