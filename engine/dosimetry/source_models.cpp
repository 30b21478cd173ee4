#include "engine/dosimetry/source_models.h"

namespace ps::dosimetry {

namespace {

// I-125 model 6711 (Oncura / GE Healthcare OncoSeed), AAPM TG-43U1 consensus data: Rivard et al.,
// Med. Phys. 31(3), 633-674 (2004), the consensus tables of model 6711: Lambda = 0.965 cGy/(h U),
// L = 0.30 cm, g_L(r) (line source), F(r, theta) and phi_an(r); half-life 59.40 d. The values were transcribed from two independent public codes that agree digit for
// digit (TPOR Amersham6711Seed.cpp, Alex Robinson; a Python 6711 seed model with the same tables).
SourceModel i125_6711() {
  SourceModel s;
  s.name = "I125_6711";
  s.description = "I-125 model 6711 (OncoSeed)";
  s.lambda_cgy_h_u = 0.965;
  s.length_cm = 0.30;
  s.half_life_d = 59.40;
  s.g_r_cm = {0.10, 0.15, 0.25, 0.50, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0};
  s.g = {1.055, 1.078, 1.082, 1.071, 1.042, 1.000, 0.908, 0.814, 0.632, 0.496, 0.364, 0.270, 0.199, 0.148, 0.109, 0.0803};
  s.f_r_cm = {0.5, 1.0, 2.0, 3.0, 4.0, 5.0};
  s.f_theta_deg = {0, 5, 10, 20, 30, 40, 50, 60, 70, 80, 90};
  s.f = {
      0.333, 0.400, 0.519, 0.716, 0.846, 0.926, 0.972, 0.991, 0.996, 1.000, 1.000,  // r = 0.5 cm
      0.370, 0.429, 0.537, 0.705, 0.834, 0.925, 0.972, 0.991, 0.996, 1.000, 1.000,  // 1
      0.442, 0.497, 0.580, 0.727, 0.842, 0.926, 0.970, 0.987, 0.996, 1.000, 1.000,  // 2
      0.488, 0.535, 0.609, 0.743, 0.846, 0.926, 0.969, 0.987, 0.995, 0.999, 1.000,  // 3
      0.520, 0.561, 0.630, 0.752, 0.848, 0.928, 0.969, 0.987, 0.995, 0.999, 1.000,  // 4
      0.550, 0.587, 0.645, 0.760, 0.852, 0.928, 0.969, 0.987, 0.995, 0.999, 1.000,  // 5
  };
  s.phi_r_cm = {0.5, 1.0, 2.0, 3.0, 4.0, 5.0};
  s.phi_an = {0.973, 0.944, 0.941, 0.942, 0.943, 0.944};
  s.citation = "Rivard et al., Med Phys 31(3):633 (2004), TG-43U1 consensus data, model 6711";
  return s;
}

// Pd-103 Theragenics model 200 (TheraSeed), AAPM TG-43U1 consensus data (Rivard et al. 2004):
// Lambda = 0.686 cGy/(h U), L = 0.423 cm, g_L(r) and F(r, theta) as published; half-life
// 16.991 d. Transcribed from TPOR Theragenics200Seed.cpp (Alex Robinson), whose g_L agrees with a
// second public table of the TG-43U1 radial dose functions. phi_an is not carried (no second
// source for it here).
SourceModel pd103_200() {
  SourceModel s;
  s.name = "Pd103_200";
  s.description = "Pd-103 Theragenics model 200 (TheraSeed)";
  s.lambda_cgy_h_u = 0.686;
  s.length_cm = 0.423;
  s.half_life_d = 16.991;
  s.g_r_cm = {0.10, 0.15, 0.25, 0.30, 0.40, 0.50, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 7.0, 10.0};
  s.g = {0.911, 1.21, 1.37, 1.38, 1.36, 1.30, 1.15, 1.000, 0.749, 0.555, 0.410, 0.302, 0.223, 0.163, 0.0887, 0.0482, 0.0262, 0.00615};
  s.f_r_cm = {0.25, 0.5, 0.75, 1.0, 2.0, 3.0, 4.0, 5.0, 7.5};
  s.f_theta_deg = {0, 1, 2, 3, 5, 7, 10, 12, 15, 20, 25, 30, 40, 50, 60, 70, 75, 80, 85, 90};
  s.f = {
      0.619, 0.617, 0.618, 0.620, 0.617, 0.579, 0.284, 0.191, 0.289, 0.496, 0.655, 0.775, 0.917, 0.945, 0.976, 0.981, 0.947, 0.992, 1.007, 1.000,  // 0.25
      0.694, 0.689, 0.674, 0.642, 0.600, 0.553, 0.496, 0.466, 0.446, 0.442, 0.497, 0.586, 0.734, 0.837, 0.906, 0.929, 0.938, 0.955, 0.973, 1.000,  // 0.5
      0.601, 0.597, 0.574, 0.577, 0.540, 0.519, 0.495, 0.486, 0.482, 0.486, 0.524, 0.585, 0.726, 0.831, 0.907, 0.954, 0.961, 0.959, 0.960, 1.000,  // 0.75
      0.541, 0.549, 0.534, 0.538, 0.510, 0.498, 0.487, 0.487, 0.490, 0.501, 0.537, 0.593, 0.727, 0.834, 0.912, 0.964, 0.978, 0.972, 0.982, 1.000,  // 1
      0.526, 0.492, 0.514, 0.506, 0.499, 0.498, 0.504, 0.512, 0.523, 0.547, 0.582, 0.633, 0.750, 0.853, 0.931, 0.989, 1.006, 1.017, 0.998, 1.000,  // 2
      0.504, 0.505, 0.517, 0.509, 0.508, 0.509, 0.519, 0.529, 0.540, 0.568, 0.603, 0.654, 0.766, 0.869, 0.942, 1.001, 1.021, 1.035, 1.030, 1.000,  // 3
      0.497, 0.513, 0.524, 0.519, 0.514, 0.521, 0.530, 0.544, 0.556, 0.585, 0.621, 0.667, 0.778, 0.881, 0.960, 1.008, 1.029, 1.046, 1.041, 1.000,  // 4
      0.513, 0.533, 0.538, 0.532, 0.531, 0.532, 0.544, 0.555, 0.567, 0.605, 0.640, 0.683, 0.784, 0.886, 0.964, 1.004, 1.024, 1.037, 1.036, 1.000,  // 5
      0.547, 0.580, 0.568, 0.570, 0.571, 0.568, 0.590, 0.614, 0.614, 0.642, 0.684, 0.719, 0.820, 0.912, 0.974, 1.011, 1.033, 1.043, 1.043, 1.000,  // 7.5
  };
  s.citation = "Rivard et al., Med Phys 31(3):633 (2004), TG-43U1 consensus data, Theragenics model 200";
  return s;
}

const std::vector<SourceModel>& models() {
  static const std::vector<SourceModel> m = {i125_6711(), pd103_200()};
  return m;
}

}  // namespace

const SourceModel* find_source_model(std::string_view name) {
  for (const SourceModel& s : models())
    if (s.name == name) return &s;
  return nullptr;
}

std::string source_model_names() {
  std::string out;
  for (const SourceModel& s : models()) out += (out.empty() ? "" : ", ") + s.name;
  return out;
}

}  // namespace ps::dosimetry
