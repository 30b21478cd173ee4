// The seed models the dose engine knows, with the AAPM TG-43U1 consensus data of each: dose-rate
// constant, line-source length, half-life, radial dose function g_L(r), 2-D anisotropy function
// F(r, theta) and the 1-D anisotropy factor phi_an(r) (kept to check the 2-D data against,
// `prostatesim validate tg43`). Tables are in centimetres and degrees as published.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace ps::dosimetry {

struct SourceModel {
  std::string name;                 // command-line name: I125_6711, Pd103_200
  std::string description;          // "I-125 Oncura/GE model 6711"
  double lambda_cgy_h_u = 0.0;      // dose-rate constant [cGy h^-1 U^-1]
  double length_cm = 0.0;           // active length L of the line source [cm]
  double half_life_d = 0.0;         // [days]
  std::vector<double> g_r_cm, g;    // radial dose function g_L(r)
  std::vector<double> f_r_cm;       // anisotropy radii [cm]
  std::vector<double> f_theta_deg;  // anisotropy angles [deg], 0..90
  std::vector<double> f;            // F[ir * f_theta_deg.size() + it]
  std::vector<double> phi_r_cm, phi_an;  // consensus 1-D anisotropy factor (empty: not known here)
  std::string citation;             // where the numbers come from
};

// The model by name (nullptr when unknown).
const SourceModel* find_source_model(std::string_view name);
// Every known name, in order (for error messages).
std::string source_model_names();

}  // namespace ps::dosimetry
