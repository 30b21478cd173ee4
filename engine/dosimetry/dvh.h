// Dose-volume indices of a structure on a dose grid (the voxels whose bit is set in the mask):
//   D_x: the least dose received by the hottest fraction x of the structure [Gy];
//   V_x: the fraction of the structure receiving at least x % of the prescription;
//   D2cc: the least dose of the hottest 2 cm^3 [Gy]; V100 [cc]: volume at or above prescription.
// The cumulative DVH is sampled at fixed steps of the prescription for the window and the report.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/dosimetry/dose_grid.h"

namespace ps::dosimetry {

// The doses of the voxels of one structure, sorted from the highest.
std::vector<float> structure_doses(const std::vector<float>& dose_gy, const std::vector<uint8_t>& mask, uint8_t bit);
double dose_to_fraction(const std::vector<float>& sorted_desc, double fraction);          // D_x [Gy]
double fraction_at_least(const std::vector<float>& sorted_desc, double gy);               // V [0..1]
double dose_to_volume(const std::vector<float>& sorted_desc, double cc, double voxel_cc); // D_cc [Gy]

struct DosimetryIndices {
  double prescription_gy = 0.0;
  double prostate_cc = 0.0, urethra_cc = 0.0, rectum_cc = 0.0;   // structure volumes on the grid
  double prostate_d90_gy = 0.0, prostate_v100 = 0.0, prostate_v150 = 0.0, prostate_v200 = 0.0;
  double urethra_d10_gy = 0.0, urethra_d30_gy = 0.0;
  double rectum_d2cc_gy = 0.0, rectum_v100_cc = 0.0;
  int seeds = 0;
};

struct DvhCurve {
  std::vector<double> dose_gy;      // abscissa, shared by the three curves
  std::vector<double> prostate, urethra, rectum;  // fraction of the structure with at least that dose
};

DosimetryIndices dosimetry_indices(const GridSpec& g, const std::vector<float>& dose_gy, const std::vector<uint8_t>& mask,
                                   double prescription_gy, int seeds);
// Cumulative DVH from 0 to 2.5 x prescription in `bins` steps.
DvhCurve dvh_curve(const std::vector<float>& dose_gy, const std::vector<uint8_t>& mask, double prescription_gy, int bins = 100);

}  // namespace ps::dosimetry
