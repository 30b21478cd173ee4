#include "engine/dosimetry/tg43_check.h"

#include <cmath>
#include <numbers>

#include "engine/dosimetry/tg43.h"

namespace ps::dosimetry {

namespace {

// I-125 model 6711, D'(along, away) / S_K [cGy h^-1 U^-1]: rows along = 0 .. 7 cm by 0.5 cm,
// columns away = 0 .. 7 cm by 1 cm (the entry on the source centre is not used). As tabulated
// beside the TG-43U1 6711 consensus data in public code for a 6711 seed model, which does not
// name its source; it matches Lambda = 0.965 at (0, 1 cm). docs/dosimetry.md.
constexpr double kAlongAway[15][8] = {
    {0.0, 0.965, 0.197, 0.0682, 0.0301, 0.0142, 0.00729, 0.00395},
    {1.524, 0.754, 0.183, 0.0657, 0.0294, 0.0139, 0.00720, 0.00391},
    {0.368, 0.427, 0.148, 0.0590, 0.0274, 0.0132, 0.00693, 0.00380},
    {0.161, 0.223, 0.110, 0.0499, 0.0244, 0.0122, 0.00651, 0.00361},
    {0.0879, 0.121, 0.0764, 0.0403, 0.0209, 0.0109, 0.00598, 0.00338},
    {0.0525, 0.0700, 0.0526, 0.0315, 0.0172, 0.00950, 0.00536, 0.00310},
    {0.0334, 0.0430, 0.0361, 0.0238, 0.0138, 0.00805, 0.00470, 0.00279},
    {0.0226, 0.0279, 0.0249, 0.0177, 0.0111, 0.00671, 0.00403, 0.00246},
    {0.0157, 0.0187, 0.0172, 0.0128, 0.00871, 0.00556, 0.00345, 0.00215},
    {0.0111, 0.0127, 0.0119, 0.00954, 0.00673, 0.00451, 0.00292, 0.00187},
    {0.00779, 0.00878, 0.00857, 0.00705, 0.00526, 0.00360, 0.00244, 0.00160},
    {0.00576, 0.00631, 0.00618, 0.00526, 0.00404, 0.00292, 0.00201, 0.00135},
    {0.00423, 0.00456, 0.00453, 0.00394, 0.00312, 0.00233, 0.00165, 0.00114},
    {0.00321, 0.00339, 0.00334, 0.00296, 0.00243, 0.00185, 0.00134, 0.000950},
    {0.00241, 0.00252, 0.00250, 0.00227, 0.00188, 0.00147, 0.00109, 0.000783},
};

}  // namespace

std::vector<Tg43Comparison> check_6711_along_away() {
  const SourceModel& s = *find_source_model("I125_6711");
  std::vector<Tg43Comparison> out;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 8; ++j) {
      const double z = 0.5 * i, y = j, r = std::hypot(z, y);
      if (r < 0.5 - 1e-9 || r > 7.0 + 1e-9) continue;
      Tg43Comparison c;
      c.along_cm = z;
      c.away_cm = y;
      c.metric = "dose rate along " + std::to_string(z).substr(0, 3) + " away " + std::to_string(j) + " cm";
      c.value = dose_rate_per_u(s, r, std::atan2(y, z));
      c.reference = kAlongAway[i][j];
      out.push_back(c);
    }
  return out;
}

std::vector<Tg43Comparison> check_6711_phi_an() {
  const SourceModel& s = *find_source_model("I125_6711");
  std::vector<Tg43Comparison> out;
  for (size_t k = 0; k < s.phi_r_cm.size(); ++k) {
    const double r = s.phi_r_cm[k];
    // phi_an(r) = (1/2) integral_0^pi D'(r, theta) sin(theta) dtheta / D'(r, 90 deg); the dose is
    // symmetric about 90 deg, so twice the half range. Simpson, 1800 panels.
    const int n = 1800;
    const double h = 0.5 * std::numbers::pi / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double t = i * h;
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += w * dose_rate_per_u(s, r, t) * std::sin(t);
    }
    const double integral = sum * h / 3.0;
    Tg43Comparison c;
    c.metric = "phi_an at " + std::to_string(r).substr(0, 3) + " cm";
    c.along_cm = 0.0;
    c.away_cm = r;
    c.value = integral / dose_rate_per_u(s, r, 0.5 * std::numbers::pi);
    c.reference = s.phi_an[k];
    out.push_back(c);
  }
  return out;
}

}  // namespace ps::dosimetry
