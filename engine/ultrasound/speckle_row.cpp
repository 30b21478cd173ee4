#include "engine/ultrasound/speckle_row.h"

#include <cstdint>

#include "engine/util/multiversion.h"

namespace ps::us {

namespace {
inline uint32_t mix(uint32_t h) {  // lowbias32, as hash32() in speckle.h
  h ^= h >> 16;
  h *= 0x7feb352dU;
  h ^= h >> 15;
  h *= 0x846ca68bU;
  h ^= h >> 16;
  return h;
}
// two node values from one hash, each the sum of two bytes (triangular on [-255, 255]: closer to a
// Gaussian than one uniform value, so few nodes under the PSF already give complex Gaussian speckle)
inline float lo16(uint32_t h) { return static_cast<float>(static_cast<int32_t>((h & 0xFFu) + ((h >> 8) & 0xFFu)) - 255); }
inline float hi16(uint32_t h) { return static_cast<float>(static_cast<int32_t>(((h >> 16) & 0xFFu) + (h >> 24)) - 255); }
}  // namespace

PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void speckle_row(const float* qx, const float* qy, const float* qz, const float* amp, float* re, float* im, int n, bool add) {
  for (int p = 0; p < n; ++p) {
    const float x = qx[p], y = qy[p], z = qz[p];
    int32_t i = static_cast<int32_t>(x), j = static_cast<int32_t>(y), k = static_cast<int32_t>(z);
    i -= x < static_cast<float>(i);  // floor
    j -= y < static_cast<float>(j);
    k -= z < static_cast<float>(k);
    // linear weights: smoothstep ones (flat at the nodes, steep mid-cell) drew the lattice cells'
    // faces as a network of dark curves through the speckle; the PSF blur that follows smooths
    // the linear weights' kinks
    const float u = x - static_cast<float>(i), v = y - static_cast<float>(j), w = z - static_cast<float>(k);
    const uint32_t hi0 = static_cast<uint32_t>(i) * 0x9E3779B1U, hi1 = hi0 + 0x9E3779B1U;
    const uint32_t hj0 = static_cast<uint32_t>(j) * 0x85EBCA77U, hj1 = hj0 + 0x85EBCA77U;
    const uint32_t hk0 = static_cast<uint32_t>(k) * 0xC2B2AE3DU, hk1 = hk0 + 0xC2B2AE3DU;
    const uint32_t h0 = mix(hi0 ^ hj0 ^ hk0), h1 = mix(hi1 ^ hj0 ^ hk0), h2 = mix(hi0 ^ hj1 ^ hk0), h3 = mix(hi1 ^ hj1 ^ hk0);
    const uint32_t h4 = mix(hi0 ^ hj0 ^ hk1), h5 = mix(hi1 ^ hj0 ^ hk1), h6 = mix(hi0 ^ hj1 ^ hk1), h7 = mix(hi1 ^ hj1 ^ hk1);
    const float w000 = (1 - u) * (1 - v) * (1 - w), w100 = u * (1 - v) * (1 - w), w010 = (1 - u) * v * (1 - w),
                w110 = u * v * (1 - w), w001 = (1 - u) * (1 - v) * w, w101 = u * (1 - v) * w, w011 = (1 - u) * v * w,
                w111 = u * v * w;
    const float r = w000 * lo16(h0) + w100 * lo16(h1) + w010 * lo16(h2) + w110 * lo16(h3) + w001 * lo16(h4) +
                    w101 * lo16(h5) + w011 * lo16(h6) + w111 * lo16(h7);
    const float m = w000 * hi16(h0) + w100 * hi16(h1) + w010 * hi16(h2) + w110 * hi16(h3) + w001 * hi16(h4) +
                    w101 * hi16(h5) + w011 * hi16(h6) + w111 * hi16(h7);
    const float s = amp[p] * (1.0f / 256.0f);
    re[p] = (add ? re[p] : 0.0f) + r * s;
    im[p] = (add ? im[p] : 0.0f) + m * s;
  }
}

}  // namespace ps::us
