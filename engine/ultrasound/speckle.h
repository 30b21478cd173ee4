// Speckle source tied to material (rest) coordinates: a complex random field on a lattice in rest
// space, hashed (no storage, no period) and trilinearly interpolated (speckle_row.h), so a sample
// that follows the tissue sees the same scatterers wherever the tissue moves (no flicker; speckle
// deforms with it). The imager multiplies it by the local backscatter amplitude and convolves it
// with the point-spread function; the envelope of the sum of many such random phasors is Rayleigh
// distributed (fully developed speckle, Burckhardt 1978; Wagner et al. 1983: SNR = mean / sd = 1.91).
// hash32() and texture_noise() (low-frequency heterogeneity) are here.
#pragma once
#include <cmath>
#include <cstdint>

namespace ps::us {

// lowbias32 (C. Wellons' hash prospector): full avalanche with two multiplies.
inline uint32_t hash32(uint32_t h) {
  h ^= h >> 16;
  h *= 0x7feb352dU;
  h ^= h >> 15;
  h *= 0x846ca68bU;
  h ^= h >> 16;
  return h;
}

// Smooth real texture in [0, 1] for low-frequency heterogeneity (fat lobules, BPH nodules), in
// lattice units: trilinear value noise.
inline float texture_noise(float x, float y, float z) {
  const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const int32_t i = static_cast<int32_t>(fx), j = static_cast<int32_t>(fy), k = static_cast<int32_t>(fz);
  float u = x - fx, v = y - fy, w = z - fz;
  u = u * u * (3 - 2 * u);
  v = v * v * (3 - 2 * v);
  w = w * w * (3 - 2 * w);
  auto val = [](int32_t a, int32_t b, int32_t c) {
    return static_cast<float>(hash32(static_cast<uint32_t>(a) * 0x27d4eb2dU ^ static_cast<uint32_t>(b) * 0x165667b1U ^
                                     static_cast<uint32_t>(c) * 0xd3a2646cU) >> 8) * (1.0f / 16777216.0f);
  };
  const float c00 = val(i, j, k) * (1 - u) + val(i + 1, j, k) * u;
  const float c10 = val(i, j + 1, k) * (1 - u) + val(i + 1, j + 1, k) * u;
  const float c01 = val(i, j, k + 1) * (1 - u) + val(i + 1, j, k + 1) * u;
  const float c11 = val(i, j + 1, k + 1) * (1 - u) + val(i + 1, j + 1, k + 1) * u;
  return ((c00 * (1 - v) + c10 * v) * (1 - w) + (c01 * (1 - v) + c11 * v) * w);
}

}  // namespace ps::us
