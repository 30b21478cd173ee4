#include "engine/dosimetry/dvh.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "engine/dosimetry/organ_mask.h"

namespace ps::dosimetry {

std::vector<float> structure_doses(const std::vector<float>& dose_gy, const std::vector<uint8_t>& mask, uint8_t bit) {
  std::vector<float> d;
  for (size_t i = 0; i < dose_gy.size() && i < mask.size(); ++i)
    if (mask[i] & bit) d.push_back(dose_gy[i]);
  std::sort(d.begin(), d.end(), std::greater<float>());
  return d;
}

double dose_to_fraction(const std::vector<float>& d, double fraction) {
  if (d.empty()) return 0.0;
  const double n = std::ceil(fraction * static_cast<double>(d.size()));
  const size_t k = static_cast<size_t>(std::clamp(n, 1.0, static_cast<double>(d.size()))) - 1;
  return d[k];
}

double fraction_at_least(const std::vector<float>& d, double gy) {
  if (d.empty()) return 0.0;
  // sorted descending: the first element below gy
  const auto it = std::lower_bound(d.begin(), d.end(), static_cast<float>(gy), std::greater_equal<float>());
  return static_cast<double>(it - d.begin()) / static_cast<double>(d.size());
}

double dose_to_volume(const std::vector<float>& d, double cc, double voxel_cc) {
  if (d.empty()) return 0.0;
  const double n = std::ceil(cc / voxel_cc);
  const size_t k = static_cast<size_t>(std::clamp(n, 1.0, static_cast<double>(d.size()))) - 1;
  return d[k];
}

DosimetryIndices dosimetry_indices(const GridSpec& g, const std::vector<float>& dose, const std::vector<uint8_t>& mask,
                                   double rx, int seeds) {
  DosimetryIndices x;
  x.prescription_gy = rx;
  x.seeds = seeds;
  const double vcc = g.voxel_cc();
  const std::vector<float> p = structure_doses(dose, mask, kProstate);
  const std::vector<float> u = structure_doses(dose, mask, kUrethra);
  const std::vector<float> r = structure_doses(dose, mask, kRectum);
  x.prostate_cc = p.size() * vcc;
  x.urethra_cc = u.size() * vcc;
  x.rectum_cc = r.size() * vcc;
  x.prostate_d90_gy = dose_to_fraction(p, 0.90);
  x.prostate_v100 = fraction_at_least(p, rx);
  x.prostate_v150 = fraction_at_least(p, 1.5 * rx);
  x.prostate_v200 = fraction_at_least(p, 2.0 * rx);
  x.urethra_d10_gy = dose_to_fraction(u, 0.10);
  x.urethra_d30_gy = dose_to_fraction(u, 0.30);
  x.rectum_d2cc_gy = dose_to_volume(r, 2.0, vcc);
  x.rectum_v100_cc = fraction_at_least(r, rx) * r.size() * vcc;
  return x;
}

DvhCurve dvh_curve(const std::vector<float>& dose, const std::vector<uint8_t>& mask, double rx, int bins) {
  DvhCurve c;
  const std::vector<float> p = structure_doses(dose, mask, kProstate);
  const std::vector<float> u = structure_doses(dose, mask, kUrethra);
  const std::vector<float> r = structure_doses(dose, mask, kRectum);
  for (int b = 0; b <= bins; ++b) {
    const double gy = 2.5 * rx * b / bins;
    c.dose_gy.push_back(gy);
    c.prostate.push_back(fraction_at_least(p, gy));
    c.urethra.push_back(fraction_at_least(u, gy));
    c.rectum.push_back(fraction_at_least(r, gy));
  }
  return c;
}

}  // namespace ps::dosimetry
