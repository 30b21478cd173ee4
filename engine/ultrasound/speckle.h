// Speckle source tied to material (rest) coordinates: a complex random field on a lattice in rest
// space, hashed (no storage, no period) and trilinearly interpolated, so a pixel that follows the
// tissue sees the same scatterers wherever the tissue moves (no flicker; speckle deforms with it).
// The imager multiplies it by the local backscatter amplitude and blurs it by the point-spread
// function; the envelope of the sum of many such random phasors is Rayleigh distributed (fully
// developed speckle, Burckhardt 1978; Wagner et al. 1983: SNR = mean / sd = 1.91).
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

// Complex lattice value at integer rest-space cell (i, j, k): two uniform values in [-1, 1).
inline void lattice_value(int32_t i, int32_t j, int32_t k, float& re, float& im) {
  const uint32_t h = hash32(static_cast<uint32_t>(i) * 0x9E3779B1U ^ static_cast<uint32_t>(j) * 0x85EBCA77U ^
                            static_cast<uint32_t>(k) * 0xC2B2AE3DU);
  re = static_cast<float>(static_cast<int32_t>(h & 0xFFFFu) - 32768) * (1.0f / 32768.0f);
  im = static_cast<float>(static_cast<int32_t>(h >> 16) - 32768) * (1.0f / 32768.0f);
}

// Complex lattice noise (trilinear with smoothstep weights) at rest point (x, y, z) given in lattice units.
inline void speckle_noise(float x, float y, float z, float& re, float& im) {
  const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const int32_t i = static_cast<int32_t>(fx), j = static_cast<int32_t>(fy), k = static_cast<int32_t>(fz);
  // smoothstep weights: the field is C1 (no kinks at lattice planes), so it holds little energy
  // above the pixel Nyquist frequency and a sub-pixel motion does not decorrelate it
  float u = x - fx, v = y - fy, w = z - fz;
  u = u * u * (3 - 2 * u);
  v = v * v * (3 - 2 * v);
  w = w * w * (3 - 2 * w);
  const uint32_t hi0 = static_cast<uint32_t>(i) * 0x9E3779B1U, hi1 = hi0 + 0x9E3779B1U;
  const uint32_t hj0 = static_cast<uint32_t>(j) * 0x85EBCA77U, hj1 = hj0 + 0x85EBCA77U;
  const uint32_t hk0 = static_cast<uint32_t>(k) * 0xC2B2AE3DU, hk1 = hk0 + 0xC2B2AE3DU;
  const uint32_t h[8] = {hash32(hi0 ^ hj0 ^ hk0), hash32(hi1 ^ hj0 ^ hk0), hash32(hi0 ^ hj1 ^ hk0), hash32(hi1 ^ hj1 ^ hk0),
                         hash32(hi0 ^ hj0 ^ hk1), hash32(hi1 ^ hj0 ^ hk1), hash32(hi0 ^ hj1 ^ hk1), hash32(hi1 ^ hj1 ^ hk1)};
  float r[8], m[8];
  for (int c = 0; c < 8; ++c) {
    r[c] = static_cast<float>(static_cast<int32_t>(h[c] & 0xFFFFu) - 32768);
    m[c] = static_cast<float>(static_cast<int32_t>(h[c] >> 16) - 32768);
  }
  const float w000 = (1 - u) * (1 - v) * (1 - w), w100 = u * (1 - v) * (1 - w), w010 = (1 - u) * v * (1 - w),
              w110 = u * v * (1 - w), w001 = (1 - u) * (1 - v) * w, w101 = u * (1 - v) * w, w011 = (1 - u) * v * w,
              w111 = u * v * w;
  re = (w000 * r[0] + w100 * r[1] + w010 * r[2] + w110 * r[3] + w001 * r[4] + w101 * r[5] + w011 * r[6] + w111 * r[7]) *
       (1.0f / 32768.0f);
  im = (w000 * m[0] + w100 * m[1] + w010 * m[2] + w110 * m[3] + w001 * m[4] + w101 * m[5] + w011 * m[6] + w111 * m[7]) *
       (1.0f / 32768.0f);
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
