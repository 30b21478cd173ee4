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

// The row loop, with `add` fixed at compile time: a run-time choice inside the loop is control
// flow, and GCC then leaves the whole loop scalar.
template <bool Add>
__attribute__((always_inline)) inline void speckle_loop(const float* __restrict qx, const float* __restrict qy, const float* __restrict qz,
                         const float* __restrict amp, float* __restrict re, float* __restrict im, int n) {
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
    if constexpr (Add) {
      re[p] += r * s;
      im[p] += m * s;
    } else {
      re[p] = 0.0f + r * s;  // 0 + x as before the split: the same value and sign of zero
      im[p] = 0.0f + m * s;
    }
  }
}
}  // namespace

PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void speckle_row(const float* qx, const float* qy, const float* qz, const float* amp, float* re, float* im, int n, bool add) {
  if (add) speckle_loop<true>(qx, qy, qz, amp, re, im, n);
  else speckle_loop<false>(qx, qy, qz, amp, re, im, n);
}

namespace {
__attribute__((always_inline)) inline void lattice_loop(const float* __restrict X0, const float* __restrict X1,
                                                        const float* __restrict X2, const float* __restrict R1,
                                                        const float* __restrict R2, float inv_step, float* __restrict q0,
                                                        float* __restrict q1, float* __restrict q2, float* __restrict q3,
                                                        float* __restrict q4, float* __restrict q5, int n) {
  for (int p = 0; p < n; ++p) {
    const float x = X0[p], y = X1[p], z = X2[p];
    q0[p] = (R1[0] * x + R1[1] * y + R1[2] * z) * inv_step;
    q1[p] = (R1[3] * x + R1[4] * y + R1[5] * z) * inv_step;
    q2[p] = (R1[6] * x + R1[7] * y + R1[8] * z) * inv_step;
    q3[p] = (R2[0] * x + R2[1] * y + R2[2] * z) * inv_step + 0.5f;
    q4[p] = (R2[3] * x + R2[4] * y + R2[5] * z) * inv_step + 0.5f;
    q5[p] = (R2[6] * x + R2[7] * y + R2[8] * z) * inv_step + 0.5f;
  }
}
}  // namespace

PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void lattice_row(const float* X0, const float* X1, const float* X2, const float* R1, const float* R2, float inv_step,
                 float* q, size_t stride, int n) {
  lattice_loop(X0, X1, X2, R1, R2, inv_step, q, q + stride, q + 2 * stride, q + 3 * stride, q + 4 * stride, q + 5 * stride, n);
}

namespace {
__attribute__((always_inline)) inline float texture_value(int32_t a, int32_t b, int32_t c) {  // as texture_noise()
  return static_cast<float>(mix(static_cast<uint32_t>(a) * 0x27d4eb2dU ^ static_cast<uint32_t>(b) * 0x165667b1U ^
                                static_cast<uint32_t>(c) * 0xd3a2646cU) >> 8) * (1.0f / 16777216.0f);
}
__attribute__((always_inline)) inline void texture_loop(const float* __restrict X0, const float* __restrict X1,
                                                        const float* __restrict X2, float inv_scale, float* __restrict out, int n) {
  for (int p = 0; p < n; ++p) {
    const float x = X0[p] * inv_scale, y = X1[p] * inv_scale, z = X2[p] * inv_scale;
    int32_t i = static_cast<int32_t>(x), j = static_cast<int32_t>(y), k = static_cast<int32_t>(z);
    i -= x < static_cast<float>(i);  // floor
    j -= y < static_cast<float>(j);
    k -= z < static_cast<float>(k);
    float u = x - static_cast<float>(i), v = y - static_cast<float>(j), w = z - static_cast<float>(k);
    u = u * u * (3 - 2 * u);
    v = v * v * (3 - 2 * v);
    w = w * w * (3 - 2 * w);
    const float c00 = texture_value(i, j, k) * (1 - u) + texture_value(i + 1, j, k) * u;
    const float c10 = texture_value(i, j + 1, k) * (1 - u) + texture_value(i + 1, j + 1, k) * u;
    const float c01 = texture_value(i, j, k + 1) * (1 - u) + texture_value(i + 1, j, k + 1) * u;
    const float c11 = texture_value(i, j + 1, k + 1) * (1 - u) + texture_value(i + 1, j + 1, k + 1) * u;
    out[p] = ((c00 * (1 - v) + c10 * v) * (1 - w) + (c01 * (1 - v) + c11 * v) * w);
  }
}
}  // namespace

PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void texture_row(const float* X0, const float* X1, const float* X2, float inv_scale, float* out, int n) {
  texture_loop(X0, X1, X2, inv_scale, out, n);
}

}  // namespace ps::us
