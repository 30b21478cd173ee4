#include "engine/ultrasound/imager.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "engine/ultrasound/speckle.h"
#include "engine/util/multiversion.h"
#include "engine/ultrasound/speckle_row.h"

namespace ps::us {

namespace {

constexpr double kPi = 3.141592653589793;
constexpr float kDisplayFloor = 0.4f;     // unit-backscatter speckle rms at 40 % of the dynamic range
constexpr float kTextureScale = 3.0e-3f;  // heterogeneity lattice (fat lobules, nodules) [m]
constexpr double kGridStep = 2.0e-3;      // displacement grid [m]
// A fixed generic rotation of rest space before the lattice, so that no anatomical plane (the
// transverse plane is often z = const) cuts the lattice along its axes (a visible square grid).
constexpr float kRot[9] = {0.8660254f, -0.3535534f, 0.3535534f, 0.0f, 0.7071068f, 0.7071068f, -0.5f, -0.6123724f, 0.6123724f};
// The scatterers are the sum of two such lattices, the second turned the other way and shifted by
// half a cell: with a lattice as coarse as the PSF, one lattice alone gave too few independent
// scatterers per resolution cell (envelope SNR 2.2-2.4 instead of Rayleigh's 1.91) and its cells
// showed as a network of dark curves; the trilinear weights' variance (1 at a node, 1/8 mid-cell)
// also averages out over two lattices whose nodes do not coincide.
constexpr float kRot2[9] = {0.6123724f, 0.6123724f, -0.5f, -0.7071068f, 0.7071068f, 0.0f, 0.3535534f, 0.3535534f, 0.8660254f};
constexpr int kTexStep = 4;
// rods are deposited per beam (per pixel before the acquisition grid): the same shaft, three times
// the density, keeps a needle in the slice saturated as it was
constexpr double kRodGain = 3.0;               // heterogeneity texture evaluated every 4 pixels

// normalised Gaussian taps of standard deviation sigma [px]
std::vector<float> gaussian_taps(double sigma) {
  const int r = std::max(1, static_cast<int>(std::ceil(2.5 * sigma)));
  std::vector<float> k(2 * r + 1);
  double sum = 0.0;
  for (int i = -r; i <= r; ++i) sum += k[i + r] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)));
  for (float& v : k) v = static_cast<float>(v / sum);
  return k;
}

// log2 to ~1e-4 (mantissa polynomial), enough for 8-bit display; x > 0
inline float fast_log2(float x) {
  const uint32_t b = std::bit_cast<uint32_t>(x);
  const float e = static_cast<float>(static_cast<int32_t>((b >> 23) & 0xFF) - 127);
  const float m = std::bit_cast<float>((b & 0x007FFFFFu) | 0x3F800000u);  // [1, 2)
  const float t = m - 1.0f;
  return e + t * (1.4425449f + t * (-0.7181452f + t * (0.4575485f + t * (-0.2779042f + t * (0.1217970f - t * 0.0258411f)))));
}

}  // namespace

// separable convolution, zero outside the buffer: `in` -> `out` along x or y. Loops run over the
// pixels for one tap at a time (contiguous, vectorisable); `pad` is scratch of w + taps floats.
// built for AVX2 and the baseline, chosen at load time: 8 floats a step instead of 4 (no FMA, so
// the same roundings as the baseline: bit-identical images)
PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void convolve_separable(const float* in, float* out, int w, int h, const float* k, int taps, bool along_x, float* pad) {
  const int r = taps / 2;
  if (along_x) {
    for (int i = 0; i < r; ++i) pad[i] = pad[w + r + i] = 0.0f;
    for (int j = 0; j < h; ++j) {
      std::memcpy(pad + r, in + static_cast<size_t>(j) * w, sizeof(float) * w);
      float* o = out + static_cast<size_t>(j) * w;
      const float k0 = k[0];
      for (int i = 0; i < w; ++i) o[i] = k0 * pad[i];
      for (int t = 1; t <= 2 * r; ++t) {
        const float kt = k[t];
        const float* a = pad + t;
        for (int i = 0; i < w; ++i) o[i] += kt * a[i];
      }
    }
  } else {
    for (int j = 0; j < h; ++j) {
      float* o = out + static_cast<size_t>(j) * w;
      const int lo = std::max(-r, -j), hi = std::min(r, h - 1 - j);
      bool first = true;
      for (int t = lo; t <= hi; ++t) {
        const float kt = k[t + r];
        const float* a = in + static_cast<size_t>(j + t) * w;
        if (first) {
          for (int i = 0; i < w; ++i) o[i] = kt * a[i];
          first = false;
        } else {
          for (int i = 0; i < w; ++i) o[i] += kt * a[i];
        }
      }
      if (first) std::fill(o, o + w, 0.0f);
    }
  }
}


// One row of the lateral PSF: out[b] = sum_t k[t] in[b + t - r], zero outside [0, n). `pad` holds
// n + 2r floats. Built like convolve_separable().
PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void convolve_row(const float* in, float* out, int n, const float* k, int r, float* pad) {
  for (int i = 0; i < r; ++i) pad[i] = pad[n + r + i] = 0.0f;
  std::memcpy(pad + r, in, sizeof(float) * n);
  const float k0 = k[0];
  for (int i = 0; i < n; ++i) out[i] = k0 * pad[i];
  for (int t = 1; t <= 2 * r; ++t) {
    const float kt = k[t];
    const float* a = pad + t;
    for (int i = 0; i < n; ++i) out[i] += kt * a[i];
  }
}

// Scan conversion and log compression (compress()): the I/Q signal of the grid (bilinear between
// beams and samples; interpolating the envelope instead filled the speckle's nulls: envelope SNR
// 2.2 instead of 1.91) at S points of each pixel, point 0 its centre. The envelope is the centre's
// |I + iQ| x TGC; the gray level is the log-compressed value averaged over the S points with
// weights wq (S > 1 where the pixel is coarser than the grid: the scan converter's anti-aliasing
// after log compression, else the display undersamples the speckle and a sub-pixel tissue motion
// changes the pixels' values), gray = a log2(env) + b0 on [0, 255].
// Only the n pixels in the view are formed (the others stay 0 from the constructor); the look-up
// tables are point-major over them (lut_i[q * n + k]). Per point, the grid's four I/Q pairs are
// read from the interleaved signal EQ (re, im of a sample side by side: two 16-byte rows) in a
// scalar loop that writes |I + iQ|^2; the square root, log, clamp and weighting then run as
// branch-free loops over contiguous pixels that the compiler vectorises (built like
// convolve_separable()). The sums keep the scalar order: the same bits on every clone.
namespace {
__attribute__((always_inline)) inline void iq_power(const float* __restrict EQ, int NB, const int* __restrict lut_i,
                                                    const float* __restrict lut_wb, const float* __restrict lut_wk,
                                                    float* __restrict mag2, size_t n) {
  const size_t row = 2 * static_cast<size_t>(NB);
  for (size_t k = 0; k < n; ++k) {
    const float* e = EQ + 2 * static_cast<size_t>(lut_i[k]);
    const float wb = lut_wb[k], wk = lut_wk[k];
    const float w00 = (1 - wk) * (1 - wb), w01 = (1 - wk) * wb, w10 = wk * (1 - wb), w11 = wk * wb;
#if defined(__SSE2__)
    // (re, im) of both beams of a row in one load; the sums in the scalar order below
    const __m128 a = _mm_mul_ps(_mm_loadu_ps(e), _mm_set_ps(w01, w01, w00, w00));
    const __m128 b = _mm_mul_ps(_mm_loadu_ps(e + row), _mm_set_ps(w11, w11, w10, w10));
    __m128 v = _mm_add_ps(a, _mm_movehl_ps(a, a));  // w00 e00 + w01 e01
    v = _mm_add_ps(v, b);                           // + w10 e10
    v = _mm_add_ps(v, _mm_movehl_ps(b, b));         // + w11 e11
    const __m128 sq = _mm_mul_ps(v, v);
    mag2[k] = _mm_cvtss_f32(_mm_add_ss(sq, _mm_shuffle_ps(sq, sq, 1)));
#else
    const float er = w00 * e[0] + w01 * e[2] + w10 * e[row] + w11 * e[row + 2];
    const float ei = w00 * e[1] + w01 * e[3] + w10 * e[row + 1] + w11 * e[row + 3];
    mag2[k] = er * er + ei * ei;
#endif
  }
}
template <bool First>
__attribute__((always_inline)) inline void log_pass(const float* __restrict mag2, float wq, const float* __restrict tgc, float a,
                                                    float b0, float* __restrict envelope, float* __restrict gray, size_t n) {
  for (size_t k = 0; k < n; ++k) {
    // mag2 >= 0 (or NaN): no errno, one vsqrtps for the lanes (-fno-math-errno on this file)
    const float env = std::sqrt(mag2[k]) * tgc[k];
    // computed for every pixel and then selected: a branch would keep the loop scalar
    const float lg = a * fast_log2(env) + b0;
    const float g = env > 1e-12f ? lg : 0.0f;
    const float c = wq * std::min(std::max(g, 0.0f), 255.0f);
    if constexpr (First) {
      envelope[k] = env;
      gray[k] = 0.0f + c;
    } else {
      gray[k] += c;
    }
  }
}
}  // namespace

PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void compress_run(const float* EQ, int NB, int S, const float* wq, const float* tgc, const int* lut_i, const float* lut_wb,
                  const float* lut_wk, float a, float b0, float* envelope, float* gray, float* mag2, uint8_t* pixels, size_t n) {
  for (int q = 0; q < S; ++q) {
    const size_t o = static_cast<size_t>(q) * n;
    iq_power(EQ, NB, lut_i + o, lut_wb + o, lut_wk + o, mag2, n);
    if (q == 0) log_pass<true>(mag2, wq[0], tgc, a, b0, envelope, gray, n);
    else log_pass<false>(mag2, wq[q], tgc, a, b0, envelope, gray, n);
  }
  for (size_t k = 0; k < n; ++k) pixels[k] = static_cast<uint8_t>(static_cast<int32_t>(std::min(std::max(gray[k], 0.0f), 255.0f)));
}

// scatter()'s arithmetic passes over a row's candidate samples, built like convolve_separable()
// (the loops live in always_inline helpers: GCC 12 does not vectorise a loop written directly in
// a function that carries target_clones and optimize("O3"))
namespace {
__attribute__((always_inline)) inline void cell_loop(const float* __restrict cs, const float* __restrict ct, int n, float gs0,
                                                     float gt0, float inv_g, int gx, int gy, int* __restrict node,
                                                     float* __restrict w00, float* __restrict w10, float* __restrict w01,
                                                     float* __restrict w11) {
  for (int i = 0; i < n; ++i) {
    const float afx = (cs[i] - gs0) * inv_g, bfy = (gt0 - ct[i]) * inv_g;
    const int a = std::min(std::max(static_cast<int>(afx), 0), gx - 2), bb = std::min(std::max(static_cast<int>(bfy), 0), gy - 2);
    const float wa = std::min(std::max(afx - a, 0.0f), 1.0f), wb = std::min(std::max(bfy - bb, 0.0f), 1.0f);
    node[i] = bb * gx + a;
    w00[i] = (1 - wa) * (1 - wb), w10[i] = wa * (1 - wb), w01[i] = (1 - wa) * wb, w11[i] = wa * wb;
  }
}
__attribute__((always_inline)) inline void rest_loop(const float* __restrict cs, const float* __restrict ct,
                                                     const float* __restrict u0, const float* __restrict u1,
                                                     const float* __restrict u2, float O0, float O1, float O2, float r0,
                                                     float r1, float r2, float p0, float p1, float p2, float* __restrict x0,
                                                     float* __restrict x1, float* __restrict x2, int n) {
  for (int i = 0; i < n; ++i) {
    const float s = cs[i], t = ct[i];
    x0[i] = O0 + s * r0 + t * p0 - u0[i];
    x1[i] = O1 + s * r1 + t * p1 - u1[i];
    x2[i] = O2 + s * r2 + t * p2 - u2[i];
  }
}
}  // namespace

// plane point (s, t) -> displacement grid cell (bb * gx + a) and its four bilinear weights
PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void cell_weights(const float* cs, const float* ct, int n, float gs0, float gt0, float inv_g, int gx, int gy, int* node,
                  float* w00, float* w10, float* w01, float* w11) {
  cell_loop(cs, ct, n, gs0, gt0, inv_g, gx, gy, node, w00, w10, w01, w11);
}

// rest point O + s right + t up - u of each plane point
PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void rest_points(const float* cs, const float* ct, const float* u0, const float* u1, const float* u2, const float* O,
                 const float* Rr, const float* Ru, float* x0, float* x1, float* x2, int n) {
  rest_loop(cs, ct, u0, u1, u2, O[0], O[1], O[2], Rr[0], Rr[1], Rr[2], Ru[0], Ru[1], Ru[2], x0, x1, x2, n);
}

PlaneImager::PlaneImager(const UltrasoundAnatomy& anatomy, const UltrasoundSettings& settings, PlaneKind kind)
    : an_(anatomy), set_(settings), kind_(kind), W_(settings.width), H_(settings.height) {
  validate(set_);
  const double r = set_.convex_radius, D = set_.depth, R = r + D;
  const double h = 0.5 * set_.fov;
  double smin, smax, tmin, tmax;
  if (kind_ == PlaneKind::Transverse) {
    smax = R * std::sin(std::min(h, 0.5 * kPi));
    smin = -smax;
    tmin = std::min(r * std::cos(h), R * std::cos(h));
    tmax = R;
  } else {
    smax = 0.5 * set_.linear_width;
    smin = -smax;
    tmin = r;
    tmax = R;
  }
  const double margin = 0.01 * std::max(smax - smin, tmax - tmin);
  smin -= margin, smax += margin, tmin -= margin, tmax += margin;
  px_ = std::max((smax - smin) / W_, (tmax - tmin) / H_);
  s0_ = 0.5 * (smin + smax) - 0.5 * (W_ - 1) * px_;
  t0_ = 0.5 * (tmin + tmax) + 0.5 * (H_ - 1) * px_;

  const size_t np = static_cast<size_t>(W_) * H_;
  img_.width = W_;
  img_.height = H_;
  img_.pixel = px_;
  img_.pixels.assign(np, 0);
  img_.envelope.assign(np, 0.0f);
  img_.label.assign(np, 255);
  img_.in_view.assign(np, 0);
  depth_.assign(np, -1.0f);
  tgc_.assign(np, 0.0f);
  mask_.assign(np, 0);

  // --- point-spread function and acquisition grid ---
  // Scatterer field: lattice step 1.5 wavelengths. The grid samples it at <= L/2 in depth and
  // <= L between beams at the deepest point of the sector (closer everywhere else), so the sampled
  // field is smooth on the grid and a sub-sample tissue motion does not sample new scatterers.
  const double lambda = wavelength();
  double L = 1.5 * lambda;
  const double arc = kind_ == PlaneKind::Transverse ? R * set_.fov : set_.linear_width;
  constexpr int kMaxSamples = 1024, kMaxBeams = 1024;
  NS_ = static_cast<int>(std::ceil(D / (0.5 * L)));
  if (NS_ > kMaxSamples) NS_ = kMaxSamples, L = std::max(L, 2.0 * D / NS_);
  const double beam_step = kind_ == PlaneKind::Transverse ? L : 0.5 * L;
  NB_ = static_cast<int>(std::ceil(arc / beam_step));
  if (NB_ > kMaxBeams) NB_ = kMaxBeams, L = std::max(L, arc / NB_ / (beam_step / L));
  NB_ = std::max(NB_, 4);
  NS_ = std::max(NS_, 4);
  dz_ = D / NS_;
  dbeam_ = kind_ == PlaneKind::Transverse ? set_.fov / NB_ : set_.linear_width / NB_;
  lattice_ = static_cast<float>(L);
  // trilinear lattice noise = white lattice values x a hat kernel of standard deviation
  // L / sqrt(6) per axis: the field's own share of the PSF
  const double sig_field = 0.408 * L;
  // elevation: the field stretched along the plane normal so that its correlation there matches
  // the slice profile (Gaussian, FWHM = slice thickness)
  const double L_elev = std::max(L, set_.slice_thickness / 2.3548 / 0.408);
  stretch_ = static_cast<float>(L / L_elev - 1.0);
  // axial: Gaussian pulse-echo spectrum of -6 dB width B f0 -> envelope FWHM 4 ln2 / (pi B f0) in
  // time, c/2 of that in depth (Szabo 2004, "Diagnostic Ultrasound Imaging", ch. 6 and 8)
  const double fwhm_ax = 4.0 * std::log(2.0) / (kPi * set_.bandwidth * set_.frequency) * kSoundSpeed / 2.0;
  const double sig_ax = fwhm_ax / 2.3548;
  const double sig_ax_disc = std::sqrt(std::max(sig_ax * sig_ax - sig_field * sig_field, 0.0)) / dz_;
  kax_ = gaussian_taps(std::max(sig_ax_disc, 0.3));
  sig_ax_total_ = std::sqrt(sig_field * sig_field + std::pow(std::max(sig_ax_disc, 0.3) * dz_, 2));
  // lateral, per depth sample
  klat_off_.assign(NS_, 0);
  klat_r_.assign(NS_, 0);
  klat_.clear();
  int rmax = 0;
  for (int k = 0; k < NS_; ++k) {
    const double z = (k + 0.5) * dz_;
    const double sig = psf_lateral_fwhm(z) / 2.3548;
    const double sd = std::sqrt(std::max(sig * sig - sig_field * sig_field, 0.0)) / lateral_spacing(k);
    const std::vector<float> taps = gaussian_taps(std::max(sd, 0.3));
    klat_off_[k] = static_cast<int>(klat_.size());
    klat_r_[k] = static_cast<int>(taps.size() / 2);
    rmax = std::max(rmax, klat_r_[k]);
    klat_.insert(klat_.end(), taps.begin(), taps.end());
  }
  pad_.assign(NB_ + 2 * rmax + 2, 0.0f);
  const size_t ng = static_cast<size_t>(NB_) * NS_;
  samp_s_.assign(ng, 0.0f);
  samp_t_.assign(ng, 0.0f);
  samp_pix_.assign(ng, -1);
  mark_.assign(ng, 1.0f);
  stop_.assign(ng, 0);
  glab_.assign(ng, 255);
  gre_.assign(ng, 0.0f);
  gim_.assign(ng, 0.0f);
  gtr_.assign(ng, 0.0f);
  gti_.assign(ng, 0.0f);
  eq_.assign(2 * (ng + NB_ + 1), 0.0f);
  rod_k_.assign(NB_, NS_);
  rod_m_.assign(NB_, 1.0f);
  beam_T_.assign(NB_, 1.0f);
  marked_.reserve(4 * static_cast<size_t>(NB_));
  sc_.assign(14 * static_cast<size_t>(std::max(NB_, (W_ - 1) / kTexStep + 2)), 0.0f);  // also texture()'s 3 rows of tx_
  sci_.assign(3 * static_cast<size_t>(NB_), 0);
  scf_.assign(NB_, 0);
  for (int k = 0; k < NS_; ++k)
    for (int b = 0; b < NB_; ++b) {
      double s, t;
      const double rho = r + (k + 0.5) * dz_;
      if (kind_ == PlaneKind::Transverse) {
        const double phi = -h + (b + 0.5) * dbeam_;
        s = rho * std::sin(phi), t = rho * std::cos(phi);
      } else {
        s = -0.5 * set_.linear_width + (b + 0.5) * dbeam_, t = rho;
      }
      const size_t g = static_cast<size_t>(k) * NB_ + b;
      samp_s_[g] = static_cast<float>(s);
      samp_t_[g] = static_cast<float>(t);
      const int i = static_cast<int>(std::lround((s - s0_) / px_)), j = static_cast<int>(std::lround((t0_ - t) / px_));
      if (i >= 0 && i < W_ && j >= 0 && j < H_) samp_pix_[g] = j * W_ + i;
    }

  const double f_mhz = set_.frequency * 1e-6;
  // display sample points of a pixel [px], the centre first, and their weights: where the pixel is
  // coarser than the grid's depth step (transverse, 0.26 mm pixels for 0.15 mm samples), the
  // centre and four points 0.3 px out on the diagonals, equally weighted
  std::vector<std::array<double, 2>> sub_at{{0.0, 0.0}};
  if (px_ > dz_) {
    constexpr double d = 0.3;
    sub_at = {{0.0, 0.0}, {-d, -d}, {d, -d}, {-d, d}, {d, d}};
  }
  sub_w_.assign(sub_at.size(), 1.0f / static_cast<float>(sub_at.size()));
  sub_ = static_cast<int>(sub_at.size());
  // grid coordinates (beam, sample) of plane point (s, t), clamped into the grid
  auto grid_of = [&](double s, double t, size_t l) {
    double depth, bf;
    if (kind_ == PlaneKind::Transverse) depth = std::hypot(s, t) - r, bf = (std::atan2(s, t) + h) / dbeam_ - 0.5;
    else depth = t - r, bf = (s + 0.5 * set_.linear_width) / dbeam_ - 0.5;
    const double kf = depth / dz_ - 0.5;
    const double bc = std::clamp(bf, 0.0, NB_ - 1.000001), kc = std::clamp(kf, 0.0, NS_ - 1.000001);
    const int b0 = std::min(static_cast<int>(bc), NB_ - 2), k0 = std::min(static_cast<int>(kc), NS_ - 2);
    lut_i_[l] = k0 * NB_ + b0;
    lut_wb_[l] = static_cast<float>(bc - b0);
    lut_wk_[l] = static_cast<float>(kc - k0);
  };
  for (int j = 0; j < H_; ++j)
    for (int i = 0; i < W_; ++i) {
      const double s = pixel_s(i), t = pixel_t(j);
      double depth = -1.0;
      if (kind_ == PlaneKind::Transverse) {
        const double rho = std::hypot(s, t), phi = std::atan2(s, t);
        if (rho >= r && rho <= R && std::abs(phi) <= h) depth = rho - r;
      } else if (std::abs(s) <= 0.5 * set_.linear_width && t >= r && t <= R) {
        depth = t - r;
      }
      if (depth < 0) continue;
      const size_t p = static_cast<size_t>(j) * W_ + i;
      img_.in_view[p] = 1;
      depth_[p] = static_cast<float>(depth);
      view_pix_.push_back(static_cast<int>(p));
      // round-trip TGC in dB: 2 * slope * f * depth
      const double tgc_db = 2.0 * set_.tgc_db_cm_mhz * f_mhz * depth * 100.0 + set_.gain_db;
      tgc_[p] = static_cast<float>(std::pow(10.0, tgc_db / 20.0));
    }
  // the scan converter's tables over the pixels in the view only, point-major (compress_run())
  const size_t nv = view_pix_.size();
  lut_i_.assign(nv * sub_, 0);
  lut_wb_.assign(nv * sub_, 0.0f);
  lut_wk_.assign(nv * sub_, 0.0f);
  tgc_v_.resize(nv);
  for (size_t v = 0; v < nv; ++v) {
    const int p = view_pix_[v];
    const double s = pixel_s(p % W_), t = pixel_t(p / W_);
    for (int q = 0; q < sub_; ++q) grid_of(s + sub_at[q][0] * px_, t + sub_at[q][1] * px_, q * nv + v);
    tgc_v_[v] = tgc_[p];
  }
  env_v_.assign(nv, 0.0f);
  gray_.assign(nv, 0.0f);
  mag2_.assign(nv, 0.0f);
  pix_v_.assign(nv, 0);

  row_q_.assign(12 * static_cast<size_t>(NB_), 0.0f);
  row_i_.assign(NB_, 0);

  // displacement grid over the window (plus one node of margin)
  g_ = kGridStep;
  gs0_ = s0_ - g_;
  gt0_ = t0_ + g_;
  gx_ = static_cast<int>(std::ceil((W_ - 1) * px_ / g_)) + 3;
  gy_ = static_cast<int>(std::ceil((H_ - 1) * px_ / g_)) + 3;
  const int nc = static_cast<int>(an_.components.size());
  field_.assign(static_cast<size_t>(nc + 1) * gx_ * gy_ * 4, 0.0f);
  tx_ = (W_ - 1) / kTexStep + 2;
  ty_ = (H_ - 1) / kTexStep + 2;
  tex_.assign(static_cast<size_t>(tx_) * ty_, 0.5f);
  for (const UsComponent& c : an_.components) {
    comp_ac_.push_back(acoustics(c.tissue));
    comp_prostate_.push_back(c.tissue == Tissue::Prostate ? 1 : 0);
  }
  rank_comp_.assign(32, 0);
  for (int c = 0; c < nc; ++c) rank_comp_[an_.components[c].priority] = c;
  rest_.resize(3 * an_.rest.size());
  for (size_t p = 0; p < an_.rest.size(); ++p)
    for (int d = 0; d < 3; ++d) rest_[3 * p + d] = static_cast<float>(an_.rest[p][d]);
  const size_t nvert = an_.rest.size() + an_.carried_particles.size();
  ps_.assign(nvert, 0.0f);
  pt_.assign(nvert, 0.0f);
  pe_.assign(nvert, 0.0f);
  xc_.assign(3 * an_.carried_particles.size(), 0.0f);
  size_t faces = 0;
  for (const auto& c : an_.components) faces += c.faces.size();
  segs_.reserve(faces);

  // calibration: rms envelope of unit-backscatter speckle through this grid and PSF, per depth
  // sample (the lateral kernel changes with depth), from the field on a fixed generic plane of
  // rest space (deterministic); averaged over the beams and +-8 neighbouring samples
  {
    const float e1[3] = {0.48f, -0.6f, 0.64f}, e2[3] = {0.8f, 0.36f, -0.48f};  // orthonormal
    std::vector<float> mean2(NS_, 0.0f);
    for (int k = 0; k < NS_; ++k) {
      for (int b = 0; b < NB_; ++b) {
        const size_t g = static_cast<size_t>(k) * NB_ + b;
        const float X[3] = {0.0311f + samp_s_[g] * e1[0] + samp_t_[g] * e2[0], 0.0417f + samp_s_[g] * e1[1] + samp_t_[g] * e2[1],
                            -0.0213f + samp_s_[g] * e1[2] + samp_t_[g] * e2[2]};
        store_rest_point(X, b);
        row_q_[6 * NB_ + b] = 1.0f;
      }
      speckle(NB_, &gre_[static_cast<size_t>(k) * NB_], &gim_[static_cast<size_t>(k) * NB_]);
    }
    blur();
    for (int k = 0; k < NS_; ++k) {
      double sum = 0.0;
      for (int b = 0; b < NB_; ++b) {
        const size_t g = static_cast<size_t>(k) * NB_ + b;
        sum += gre_[g] * gre_[g] + gim_[g] * gim_[g];
      }
      mean2[k] = static_cast<float>(sum / NB_);
    }
    calib_.assign(NS_, 1.0f);
    line_gain_.assign(NS_, 1.0f);
    const int win = kind_ == PlaneKind::Transverse ? 8 : NS_;
    for (int k = 0; k < NS_; ++k) {
      double sum = 0.0;
      int n = 0;
      for (int q = std::max(0, k - win); q <= std::min(NS_ - 1, k + win); ++q) sum += mean2[q], ++n;
      calib_[k] = static_cast<float>(1.0 / std::sqrt(std::max(sum / n, 1e-20)));
      // a unit reflection, one per beam at this depth, peaks at kax[centre] after the blur, then
      // x calib: scale it to peak at the unit-backscatter speckle rms
      line_gain_[k] = 1.0f / (kax_[kax_.size() / 2] * calib_[k]);
    }
    std::fill(gre_.begin(), gre_.end(), 0.0f);
    std::fill(gim_.begin(), gim_.end(), 0.0f);
  }
}

double PlaneImager::psf_lateral_fwhm(double z) const {
  // pulse-echo beam = transmit x receive profiles (Gaussian beams: 1/sigma^2 adds). Transmit: fixed
  // focus, FWHM lambda F at the focus, widening as a Gaussian beam with a depth of field 7 lambda F^2
  // (Szabo 2004, ch. 6); receive: dynamic focus with the aperture, f-number z / aperture, >= 2.5.
  const double lambda = wavelength(), F = set_.f_number;
  const double zr = 3.5 * lambda * F * F;
  const double dzf = (z - set_.focus_depth) / zr;
  const double w_tx = lambda * F * std::sqrt(1.0 + dzf * dzf);
  const double w_rx = lambda * std::max(2.5, z / set_.rx_aperture);
  const double w = 1.0 / std::sqrt(1.0 / (w_tx * w_tx) + 1.0 / (w_rx * w_rx));
  const double sig_field = 0.408 * lattice_;
  return std::max(w, 2.3548 * sig_field);
}

double PlaneImager::lateral_spacing(int k) const {
  if (kind_ == PlaneKind::Sagittal) return dbeam_;
  return (set_.convex_radius + (k + 0.5) * dz_) * dbeam_;
}

void PlaneImager::grid_coords(float s, float t, float* bf, float* kf) const {
  const float r = static_cast<float>(set_.convex_radius), dz = static_cast<float>(dz_);
  if (kind_ == PlaneKind::Transverse) {
    const float rho = std::sqrt(s * s + t * t), phi = std::atan2(s, t);
    *bf = (phi + static_cast<float>(0.5 * set_.fov)) / static_cast<float>(dbeam_) - 0.5f;
    *kf = (rho - r) / dz - 0.5f;
  } else {
    *bf = (s + static_cast<float>(0.5 * set_.linear_width)) / static_cast<float>(dbeam_) - 0.5f;
    *kf = (t - r) / dz - 0.5f;
  }
}

PlaneFrame PlaneImager::frame(const ProbeView& pr) const {
  PlaneFrame f;
  f.up = pr.anterior;
  if (kind_ == PlaneKind::Transverse) {
    f.origin = pr.tip_centre - set_.transverse_back * pr.axis;
    f.right = pr.lateral;
  } else {
    f.origin = pr.tip_centre - (set_.linear_front + 0.5 * set_.linear_width) * pr.axis;
    f.right = -pr.axis;
  }
  f.normal = f.right.cross(f.up);
  return f;
}

void PlaneImager::world_to_pixel(const ProbeView& pr, const Vec3& p, double* col, double* row, double* elevation) const {
  const PlaneFrame f = frame(pr);
  const Vec3 d = p - f.origin;
  *col = (d.dot(f.right) - s0_) / px_;
  *row = (t0_ - d.dot(f.up)) / px_;
  if (elevation) *elevation = d.dot(f.normal);
}

Vec3 PlaneImager::pixel_to_world(const ProbeView& pr, double col, double row) const {
  const PlaneFrame f = frame(pr);
  return f.origin + pixel_s(col) * f.right + pixel_t(row) * f.up;
}

void PlaneImager::beam_dir(float s, float t, float* bs, float* bt) const {
  if (kind_ == PlaneKind::Sagittal) {
    *bs = 0.0f, *bt = 1.0f;
    return;
  }
  const float n = std::sqrt(s * s + t * t);
  if (n < 1e-9f) {
    *bs = 0.0f, *bt = 1.0f;
  } else {
    *bs = s / n, *bt = t / n;
  }
}
const UsImage& PlaneImager::render(const UltrasoundScene& sc) {
  if (sc.particle_count != static_cast<int>(an_.rest.size()) || (sc.particle_count > 0 && !sc.x))
    throw std::invalid_argument("ultrasound: the scene has " + std::to_string(sc.particle_count) +
                                " particle positions, the anatomy " + std::to_string(an_.rest.size()));
  const PlaneFrame f = frame(sc.probe);
  const float O[3] = {float(f.origin.x()), float(f.origin.y()), float(f.origin.z())};
  const float Rr[3] = {float(f.right.x()), float(f.right.y()), float(f.right.z())};
  const float Ru[3] = {float(f.up.x()), float(f.up.y()), float(f.up.z())};
  const float Rn[3] = {float(f.normal.x()), float(f.normal.y()), float(f.normal.z())};
  // carried vertices (seminal vesicles) from the particles that carry them
  for (size_t v = 0; v < an_.carried_particles.size(); ++v) {
    float q[3] = {float(an_.carried_offsets[v].x()), float(an_.carried_offsets[v].y()), float(an_.carried_offsets[v].z())};
    for (int k = 0; k < 4; ++k) {
      const float* xp = sc.x + 3 * static_cast<size_t>(an_.carried_particles[v][k]);
      const float w = an_.carried_weights[v][k];
      q[0] += w * xp[0], q[1] += w * xp[1], q[2] += w * xp[2];
    }
    for (int d = 0; d < 3; ++d) xc_[3 * v + d] = q[d];
  }
  const int nvert = sc.particle_count + static_cast<int>(an_.carried_particles.size());
  for (int p = 0; p < nvert; ++p) {
    const float* xp = vertex(sc, p);
    const float d0 = xp[0] - O[0], d1 = xp[1] - O[1], d2 = xp[2] - O[2];
    ps_[p] = d0 * Rr[0] + d1 * Rr[1] + d2 * Rr[2];
    pt_[p] = d0 * Ru[0] + d1 * Ru[1] + d2 * Ru[2];
    pe_[p] = d0 * Rn[0] + d1 * Rn[1] + d2 * Rn[2];
  }
  cut_surfaces(sc, f);
  fill_labels();
  wall_bands();
  displacement_fields(sc, f);
  texture(f);
  scatter(sc, f);
  coherent_surfaces();
  coherent_rods(sc, f);
  reverberation();
  transmission(sc, f);
  blur();
  calibrate();
  compress();
  overlays(sc, f);
  return img_;
}

void PlaneImager::cut_surfaces(const UltrasoundScene& sc, const PlaneFrame& f) {
  segs_.clear();
  for (int c = 0; c < static_cast<int>(an_.components.size()); ++c) {
    for (const auto& fc : an_.components[c].faces) {
      const int v[3] = {fc[0], fc[1], fc[2]};
      const float e[3] = {pe_[v[0]], pe_[v[1]], pe_[v[2]]};
      const bool neg[3] = {e[0] < 0.0f, e[1] < 0.0f, e[2] < 0.0f};
      if (neg[0] == neg[1] && neg[1] == neg[2]) continue;
      float pts[2][2];
      int n = 0;
      for (int k = 0; k < 3 && n < 2; ++k) {
        const int a = k, b = (k + 1) % 3;
        if (neg[a] == neg[b]) continue;
        const float u = e[a] / (e[a] - e[b]);
        pts[n][0] = ps_[v[a]] + u * (ps_[v[b]] - ps_[v[a]]);
        pts[n][1] = pt_[v[a]] + u * (pt_[v[b]] - pt_[v[a]]);
        ++n;
      }
      if (n != 2 || !std::isfinite(pts[0][0] + pts[0][1] + pts[1][0] + pts[1][1])) continue;
      // outward face normal from the current positions, in plane coordinates
      float a1[3], a2[3];
      const float *x0 = vertex(sc, v[0]), *x1 = vertex(sc, v[1]), *x2 = vertex(sc, v[2]);
      for (int d = 0; d < 3; ++d) {
        a1[d] = x1[d] - x0[d];
        a2[d] = x2[d] - x0[d];
      }
      const float nx = a1[1] * a2[2] - a1[2] * a2[1], ny = a1[2] * a2[0] - a1[0] * a2[2], nz = a1[0] * a2[1] - a1[1] * a2[0];
      const float nl = std::sqrt(nx * nx + ny * ny + nz * nz);
      Seg s;
      s.s0 = pts[0][0], s.t0 = pts[0][1], s.s1 = pts[1][0], s.t1 = pts[1][1];
      const double inv = nl > 0 ? 1.0 / nl : 0.0;
      s.nr = static_cast<float>((nx * f.right.x() + ny * f.right.y() + nz * f.right.z()) * inv);
      s.nu = static_cast<float>((nx * f.up.x() + ny * f.up.y() + nz * f.up.z()) * inv);
      s.comp = c;
      segs_.push_back(s);
    }
  }
}

void PlaneImager::fill_labels() {
  std::fill(mask_.begin(), mask_.end(), 0u);
  const float inv = static_cast<float>(1.0 / px_);
  for (const Seg& s : segs_) {
    const float x0 = (s.s0 - static_cast<float>(s0_)) * inv, y0 = (static_cast<float>(t0_) - s.t0) * inv;
    const float x1 = (s.s1 - static_cast<float>(s0_)) * inv, y1 = (static_cast<float>(t0_) - s.t1) * inv;
    if (y0 == y1) continue;
    // rows whose centre lies in [min y, max y): half-open, so a loop's rows toggle an even number of times
    const int ja = std::max(0, static_cast<int>(std::ceil(std::min(y0, y1))));
    const int jb = std::min(H_ - 1, static_cast<int>(std::ceil(std::max(y0, y1))) - 1);
    const uint32_t bit = 1u << an_.components[s.comp].priority;
    const float slope = (x1 - x0) / (y1 - y0);
    for (int j = ja; j <= jb; ++j) {
      int c = static_cast<int>(std::ceil(x0 + (static_cast<float>(j) - y0) * slope));
      if (c >= W_) continue;
      if (c < 0) c = 0;
      mask_[static_cast<size_t>(j) * W_ + c] ^= bit;
    }
  }
  for (int j = 0; j < H_; ++j) {
    uint32_t m = 0;
    uint32_t* row = &mask_[static_cast<size_t>(j) * W_];
    uint8_t* lab = &img_.label[static_cast<size_t>(j) * W_];
    for (int i = 0; i < W_; ++i) {
      m ^= row[i];
      lab[i] = m ? static_cast<uint8_t>(rank_comp_[std::countr_zero(m)]) : uint8_t{255};
    }
  }
}

void PlaneImager::wall_bands() {
  const float inv = static_cast<float>(1.0 / px_);
  for (const Seg& s : segs_) {
    const UsComponent& comp = an_.components[s.comp];
    const float wall = acoustics(comp.tissue).wall;
    if (wall <= 0.0f) continue;
    const float rw = wall * inv;
    const float x0 = (s.s0 - static_cast<float>(s0_)) * inv, y0 = (static_cast<float>(t0_) - s.t0) * inv;
    const float x1 = (s.s1 - static_cast<float>(s0_)) * inv, y1 = (static_cast<float>(t0_) - s.t1) * inv;
    const int ia = std::max(0, static_cast<int>(std::floor(std::min(x0, x1) - rw)));
    const int ib = std::min(W_ - 1, static_cast<int>(std::ceil(std::max(x0, x1) + rw)));
    const int ja = std::max(0, static_cast<int>(std::floor(std::min(y0, y1) - rw)));
    const int jb = std::min(H_ - 1, static_cast<int>(std::ceil(std::max(y0, y1) + rw)));
    const float dx = x1 - x0, dy = y1 - y0, l2 = dx * dx + dy * dy;
    const uint8_t wall_label = static_cast<uint8_t>(64 + s.comp);
    for (int j = ja; j <= jb; ++j)
      for (int i = ia; i <= ib; ++i) {
        uint8_t& lab = img_.label[static_cast<size_t>(j) * W_ + i];
        if (lab == s.comp || (lab >= 64 && lab != 255)) continue;
        if (lab != 255 && an_.components[lab].priority < comp.priority) continue;  // an organ inside wins
        float u = l2 > 0 ? ((i - x0) * dx + (j - y0) * dy) / l2 : 0.0f;
        u = std::clamp(u, 0.0f, 1.0f);
        const float ex = i - (x0 + u * dx), ey = j - (y0 + u * dy);
        if (ex * ex + ey * ey <= rw * rw) lab = wall_label;
      }
  }
}

void PlaneImager::displacement_fields(const UltrasoundScene& sc, const PlaneFrame&) {
  std::fill(field_.begin(), field_.end(), 0.0f);
  const int nc = static_cast<int>(an_.components.size());
  const size_t nodes = static_cast<size_t>(gx_) * gy_;
  float* all = &field_[static_cast<size_t>(nc) * nodes * 4];
  const float g = static_cast<float>(g_), gs0 = static_cast<float>(gs0_), gt0 = static_cast<float>(gt0_);
  for (int c = 0; c < nc; ++c) {
    const UsComponent& comp = an_.components[c];
    const float R = static_cast<float>(1.6 * (comp.spacing > 0 ? comp.spacing : 5e-3));
    const float R2 = R * R;
    float* fc = &field_[static_cast<size_t>(c) * nodes * 4];
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      const float e = pe_[p];
      if (!(std::abs(e) < R)) continue;
      const float s = ps_[p], t = pt_[p];
      const int a0 = std::max(0, static_cast<int>(std::ceil((s - R - gs0) / g)));
      const int a1 = std::min(gx_ - 1, static_cast<int>(std::floor((s + R - gs0) / g)));
      const int b0 = std::max(0, static_cast<int>(std::ceil((gt0 - t - R) / g)));
      const int b1 = std::min(gy_ - 1, static_cast<int>(std::floor((gt0 - t + R) / g)));
      if (a0 > a1 || b0 > b1) continue;
      const float u0 = sc.x[3 * p] - rest_[3 * p], u1 = sc.x[3 * p + 1] - rest_[3 * p + 1], u2 = sc.x[3 * p + 2] - rest_[3 * p + 2];
      for (int b = b0; b <= b1; ++b) {
        const float dt = gt0 - b * g - t;
        for (int a = a0; a <= a1; ++a) {
          const float ds = gs0 + a * g - s;
          const float d2 = ds * ds + dt * dt + e * e;
          if (d2 >= R2) continue;
          const float q = 1.0f - d2 / R2, w = q * q;
          const size_t n = (static_cast<size_t>(b) * gx_ + a) * 4;
          fc[n] += w * u0, fc[n + 1] += w * u1, fc[n + 2] += w * u2, fc[n + 3] += w;
          all[n] += w * u0, all[n + 1] += w * u1, all[n + 2] += w * u2, all[n + 3] += w;
        }
      }
    }
  }
  for (size_t n = 0; n < nodes; ++n) {
    float* a = &all[n * 4];
    if (a[3] > 1e-6f) {
      const float iw = 1.0f / a[3];
      a[0] *= iw, a[1] *= iw, a[2] *= iw;
    } else {
      a[0] = a[1] = a[2] = 0.0f;
    }
  }
  for (int c = 0; c < nc; ++c) {
    float* fc = &field_[static_cast<size_t>(c) * nodes * 4];
    for (size_t n = 0; n < nodes; ++n) {
      float* v = &fc[n * 4];
      if (v[3] > 1e-6f) {
        const float iw = 1.0f / v[3];
        v[0] *= iw, v[1] *= iw, v[2] *= iw;
      } else {
        v[0] = all[n * 4], v[1] = all[n * 4 + 1], v[2] = all[n * 4 + 2];
      }
    }
  }
}
void PlaneImager::texture(const PlaneFrame& f) {
  // low-frequency heterogeneity at the coarse nodes (every kTexStep pixels), at the rest point of
  // the mean displacement field
  const size_t nodes = static_cast<size_t>(gx_) * gy_;
  const float invT = 1.0f / kTextureScale;
  const float* all = &field_[an_.components.size() * nodes * 4];
  float* const X0 = sc_.data();  // scatter()'s row scratch, free before it runs
  float* const X1 = X0 + tx_;
  float* const X2 = X1 + tx_;
  for (int tb = 0; tb < ty_; ++tb) {
    for (int ta = 0; ta < tx_; ++ta) {
      const double s = pixel_s(ta * kTexStep), t = pixel_t(tb * kTexStep);
      const Vec3 xw = f.origin + s * f.right + t * f.up;
      const int a = std::clamp(static_cast<int>((s - gs0_) / g_), 0, gx_ - 2), b = std::clamp(static_cast<int>((gt0_ - t) / g_), 0, gy_ - 2);
      const float wa = std::clamp(static_cast<float>((s - gs0_) / g_ - a), 0.0f, 1.0f), wb = std::clamp(static_cast<float>((gt0_ - t) / g_ - b), 0.0f, 1.0f);
      const float* n00 = &all[(static_cast<size_t>(b) * gx_ + a) * 4];
      const float* n10 = n00 + 4;
      const float* n01 = n00 + static_cast<size_t>(gx_) * 4;
      const float* n11 = n01 + 4;
      float X[3];
      for (int d = 0; d < 3; ++d)
        X[d] = static_cast<float>(xw[d]) - ((1 - wa) * (1 - wb) * n00[d] + wa * (1 - wb) * n10[d] + (1 - wa) * wb * n01[d] + wa * wb * n11[d]);
      X0[ta] = X[0], X1[ta] = X[1], X2[ta] = X[2];
    }
    texture_row(X0, X1, X2, invT, &tex_[static_cast<size_t>(tb) * tx_], tx_);
  }
}

void PlaneImager::scatter(const UltrasoundScene& sc, const PlaneFrame& f) {
  const size_t nodes = static_cast<size_t>(gx_) * gy_;
  const RestVolume& vol = an_.prostate_echo;
  const float vinv = static_cast<float>(1.0 / vol.step);
  const float vo[3] = {float(vol.origin.x()), float(vol.origin.y()), float(vol.origin.z())};
  const float inv_g = static_cast<float>(1.0 / g_), inv_px = static_cast<float>(1.0 / px_);
  const float O[3] = {float(f.origin.x()), float(f.origin.y()), float(f.origin.z())};
  const float Rr[3] = {float(f.right.x()), float(f.right.y()), float(f.right.z())};
  const float Ru[3] = {float(f.up.x()), float(f.up.y()), float(f.up.z())};
  const float Rn[3] = {float(f.normal.x()), float(f.normal.y()), float(f.normal.z())};
  // elevation of the plane above a reference point on the probe axis (the foot of the world
  // origin on it): the field is stretched along the normal about that point, so turning or sliding
  // the probe moves the slice through the scatterers at the rate the tissue crosses it
  const Vec3 foot = sc.probe.tip_centre - sc.probe.tip_centre.dot(sc.probe.axis) * sc.probe.axis;
  const float e0 = static_cast<float>((f.origin - foot).dot(f.normal));
  const float st = stretch_;
  // Everything the loop reads, in locals: it stores through uint8_t (stop_), which may alias any
  // object, so members and vector data pointers would otherwise be reloaded for every sample.
  const int NB = NB_, NS = NS_, gx = gx_, gy = gy_, tx = tx_, ty = ty_;
  const float gs0 = static_cast<float>(gs0_), gt0 = static_cast<float>(gt0_);
  const float s0 = static_cast<float>(s0_), t0 = static_cast<float>(t0_);
  const int* const samp_pix = samp_pix_.data();
  const float* const samp_s = samp_s_.data();
  const float* const samp_t = samp_t_.data();
  const uint8_t* const label = img_.label.data();
  const TissueAcoustics* const comp_ac = comp_ac_.data();
  const uint8_t* const comp_prostate = comp_prostate_.data();
  const float* const field = field_.data();
  const float* const tex = tex_.data();
  const float* const vval = vol.value.data();
  const bool vol_empty = vol.empty();
  const int vnx = vol.nx, vny = vol.ny, vnz = vol.nz;
  uint8_t* const stop = stop_.data();
  uint8_t* const glab = glab_.data();
  float* const gre = gre_.data();
  float* const gim = gim_.data();
  float* const rq = row_q_.data();
  int* const row_i = row_i_.data();
  const size_t n9 = 9 * static_cast<size_t>(NB), n6 = 6 * static_cast<size_t>(NB);
  // per-row scratch (sc_ holds 14 rows of NB): the candidates' beam, component, flags and
  // backscatter (pass 1), then their plane point, grid cell and weights, displacement and rest point
  float* const cs = sc_.data();
  float* const ct = cs + NB;
  float* const cw00 = cs + 2 * NB;
  float* const cw10 = cs + 3 * NB;
  float* const cw01 = cs + 4 * NB;
  float* const cw11 = cs + 5 * NB;
  float* const cu0 = cs + 6 * NB;
  float* const cu1 = cs + 7 * NB;
  float* const cu2 = cs + 8 * NB;
  float* const cx0 = cs + 9 * NB;
  float* const cx1 = cs + 10 * NB;
  float* const cx2 = cs + 11 * NB;
  float* const cecho = cs + 12 * NB;
  int* const cb = sci_.data();
  int* const cnode = cb + NB;
  int* const ccomp = cb + 2 * NB;
  uint8_t* const cflag = scf_.data();
  constexpr uint8_t kWall = 1, kGland = 2, kHetero = 4;
  for (int k = 0; k < NS; ++k) {
    const size_t row = static_cast<size_t>(k) * NB;
    std::fill(gre + row, gre + row + NB, 0.0f);
    std::fill(gim + row, gim + row + NB, 0.0f);
    std::fill(stop + row, stop + row + NB, uint8_t{0});
    // 1. candidates: samples in tissue with an echo or in the gland (scalar: label look-ups)
    int nc = 0;
    for (int b = 0; b < NB; ++b) {
      const int p = samp_pix[row + b];
      const uint8_t lab = p >= 0 ? label[p] : uint8_t{255};
      glab[row + b] = lab;  // transmission() reads them in grid order
      if (lab == 255) continue;
      const int c = lab & 63;
      const TissueAcoustics& ac = comp_ac[c];
      const bool wall = lab >= 64;
      const bool prostate = comp_prostate[c] != 0;
      const float echo = wall ? ac.wall_echo : ac.echo;
      if (echo <= 0.0f && !prostate) continue;
      cb[nc] = b;
      ccomp[nc] = c;
      cflag[nc] = static_cast<uint8_t>((wall ? kWall : 0) | (!wall && prostate && !vol_empty ? kGland : 0) |
                                       (!wall && ac.hetero > 0.0f ? kHetero : 0));
      cecho[nc] = echo;
      cs[nc] = samp_s[row + b];
      ct[nc] = samp_t[row + b];
      ++nc;
    }
    // 2. displacement grid cell and bilinear weights (branch-free arithmetic, vectorised)
    cell_weights(cs, ct, nc, gs0, gt0, inv_g, gx, gy, cnode, cw00, cw10, cw01, cw11);
    // 3. the component's displacement there (scalar: its grid's nodes)
    for (int i = 0; i < nc; ++i) {
      const float* n00 = field + (static_cast<size_t>(ccomp[i]) * nodes + static_cast<size_t>(cnode[i])) * 4;
      const float* n10 = n00 + 4;
      const float* n01 = n00 + static_cast<size_t>(gx) * 4;
      const float* n11 = n01 + 4;
      const float w00 = cw00[i], w10 = cw10[i], w01 = cw01[i], w11 = cw11[i];
      cu0[i] = w00 * n00[0] + w10 * n10[0] + w01 * n01[0] + w11 * n11[0];
      cu1[i] = w00 * n00[1] + w10 * n10[1] + w01 * n01[1] + w11 * n11[1];
      cu2[i] = w00 * n00[2] + w10 * n10[2] + w01 * n01[2] + w11 * n11[2];
    }
    // 4. rest point X = x - u (vectorised)
    rest_points(cs, ct, cu0, cu1, cu2, O, Rr, Ru, cx0, cx1, cx2, nc);
    // 5. the gland's echo from its rest-space volume (zones, lesion, urethra, calcifications) and
    // the low-frequency texture (fat lobules, nodules; bilinear on the coarse pixel grid)
    for (int i = 0; i < nc; ++i) {
      const uint8_t fl = cflag[i];
      if (!(fl & (kGland | kHetero))) continue;
      float echo = cecho[i];
      if (fl & kGland) {
        const float qx = (cx0[i] - vo[0]) * vinv, qy = (cx1[i] - vo[1]) * vinv, qz = (cx2[i] - vo[2]) * vinv;
        if (qx >= 0 && qy >= 0 && qz >= 0 && qx < vnx - 1 && qy < vny - 1 && qz < vnz - 1) {
          const int ix = static_cast<int>(qx), iy = static_cast<int>(qy), iz = static_cast<int>(qz);
          const float fu = qx - ix, fv = qy - iy, fw = qz - iz;
          const float* e0p = &vval[(static_cast<size_t>(iz) * vny + iy) * vnx + ix];
          const float* e1p = e0p + static_cast<size_t>(vnx) * vny;
          const int sx = 1, sy = vnx;
          const float c0 = (e0p[0] * (1 - fu) + e0p[sx] * fu) * (1 - fv) + (e0p[sy] * (1 - fu) + e0p[sy + sx] * fu) * fv;
          const float c1 = (e1p[0] * (1 - fu) + e1p[sx] * fu) * (1 - fv) + (e1p[sy] * (1 - fu) + e1p[sy + sx] * fu) * fv;
          echo = c0 * (1 - fw) + c1 * fw;
          stop[row + cb[i]] = echo >= kCalcificationEcho;
        }
      }
      if (fl & kHetero) {
        const float tc = std::clamp((cs[i] - s0) * inv_px * (1.0f / kTexStep), 0.0f, tx - 1.001f);
        const float tr = std::clamp((t0 - ct[i]) * inv_px * (1.0f / kTexStep), 0.0f, ty - 1.001f);
        const int ta = static_cast<int>(tc), tb = static_cast<int>(tr);
        const float tu = tc - ta, tv = tr - tb;
        const float* q = &tex[static_cast<size_t>(tb) * tx + ta];
        const float tval = (q[0] * (1 - tu) + q[1] * tu) * (1 - tv) + (q[tx] * (1 - tu) + q[tx + 1] * tu) * tv;
        echo *= std::max(0.05f, 1.0f + comp_ac[ccomp[i]].hetero * (2.0f * tval - 1.0f));
      }
      cecho[i] = echo;
    }
    // 6. elevation stretch (the rest point's height above the slice, scaled), then the samples
    // with an echo compacted into the noise kernel's slots
    int na = 0;
    for (int i = 0; i < nc; ++i) {
      if (cecho[i] <= 0.0f) continue;
      const float el = e0 - (cu0[i] * Rn[0] + cu1[i] * Rn[1] + cu2[i] * Rn[2]);
      row_i[na] = cb[i];
      rq[n9 + na] = cx0[i] + st * el * Rn[0];
      rq[n9 + NB + na] = cx1[i] + st * el * Rn[1];
      rq[n9 + 2 * NB + na] = cx2[i] + st * el * Rn[2];
      rq[n6 + na] = cecho[i];
      ++na;
    }
    float* re = rq + 7 * static_cast<size_t>(NB);
    float* im = rq + 8 * static_cast<size_t>(NB);
    speckle(na, re, im);
    float* cr = gre + row;
    float* ci = gim + row;
    for (int a = 0; a < na; ++a) cr[row_i[a]] = re[a], ci[row_i[a]] = im[a];
  }
}

void PlaneImager::store_rest_point(const float* X, int a) {
  const size_t n = static_cast<size_t>(NB_);
  row_q_[9 * n + a] = X[0];
  row_q_[10 * n + a] = X[1];
  row_q_[11 * n + a] = X[2];
}

void PlaneImager::speckle(int na, float* re, float* im) {
  const size_t n = static_cast<size_t>(NB_);
  lattice_row(&row_q_[9 * n], &row_q_[10 * n], &row_q_[11 * n], kRot, kRot2, 1.0f / lattice_, &row_q_[0], n, na);
  speckle_row(&row_q_[0], &row_q_[n], &row_q_[2 * n], &row_q_[6 * n], re, im, na, false);
  speckle_row(&row_q_[3 * n], &row_q_[4 * n], &row_q_[5 * n], &row_q_[6 * n], re, im, na, true);
}

void PlaneImager::splat(float s, float t, float amp) {
  float bf, kf;
  grid_coords(s, t, &bf, &kf);
  if (!(bf >= 0.0f && kf >= 0.0f && bf < NB_ - 1 && kf < NS_ - 1)) return;
  const int i = static_cast<int>(bf), j = static_cast<int>(kf);
  const float u = bf - i, v = kf - j;
  const size_t p = static_cast<size_t>(j) * NB_ + i;
  const float g0 = amp * line_gain_[j], g1 = amp * line_gain_[j + 1];
  gre_[p] += g0 * (1 - u) * (1 - v);
  gre_[p + 1] += g0 * u * (1 - v);
  gre_[p + NB_] += g1 * (1 - u) * v;
  gre_[p + NB_ + 1] += g1 * u * v;
}

void PlaneImager::coherent_surfaces() {
  for (const Seg& s : segs_) {
    const TissueAcoustics& ac = acoustics(an_.components[s.comp].tissue);
    if (ac.interface <= 0.0f && ac.diffuse <= 0.0f) continue;
    float bs, bt;
    beam_dir(0.5f * (s.s0 + s.s1), 0.5f * (s.t0 + s.t1), &bs, &bt);
    const float c = std::abs(s.nr * bs + s.nu * bt);  // cosine of the angle of incidence
    const float c2 = c * c;
    const float amp = ac.interface * c2 * c2 + ac.diffuse;
    const float len = std::sqrt((s.s1 - s.s0) * (s.s1 - s.s0) + (s.t1 - s.t0) * (s.t1 - s.t0));
    const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5f * static_cast<float>(px_)))));
    const float step = len / n;
    for (int k = 0; k < n; ++k) {
      const float u = (k + 0.5f) / n;
      const float ss = s.s0 + u * (s.s1 - s.s0), tt = s.t0 + u * (s.t1 - s.t0);
      float bf, kf;
      grid_coords(ss, tt, &bf, &kf);
      const int kk = std::clamp(static_cast<int>(kf), 0, NS_ - 1);
      splat(ss, tt, amp * step / static_cast<float>(lateral_spacing(kk)));  // density per beam
    }
  }
}

void PlaneImager::coherent_rods(const UltrasoundScene& sc, const PlaneFrame& f) {
  const double sig_e = set_.slice_thickness / 2.355;  // elevation beam profile (Gaussian)
  for (const Rod& rod : sc.rods) {
    const Vec3 da = rod.a - f.origin, db = rod.b - f.origin;
    const double sa = da.dot(f.right), ta = da.dot(f.up), ea = da.dot(f.normal);
    const double sb = db.dot(f.right), tb = db.dot(f.up), eb = db.dot(f.normal);
    const double len = (rod.b - rod.a).norm();
    if (!std::isfinite(len) || len <= 0) continue;
    const double ar = (sb - sa) / len, au = (tb - ta) / len;  // in-plane part of the rod axis
    const double step = 0.5 * px_;
    const int n = static_cast<int>(std::ceil(len / step));
    if (n > 100000) continue;  // absurd rod: skip rather than stall
    for (int k = 0; k <= n; ++k) {
      const double u = static_cast<double>(k) / n;
      const double e = std::max(0.0, std::abs(ea + u * (eb - ea)) - rod.radius);
      const double we = std::exp(-0.5 * e * e / (sig_e * sig_e));
      if (we < 0.02) continue;
      float s = static_cast<float>(sa + u * (sb - sa)), t = static_cast<float>(ta + u * (tb - ta));
      float bs, bt;
      beam_dir(s, t, &bs, &bt);
      const double ca = ar * bs + au * bt;          // cosine between the rod axis and the beam
      const double sn2 = std::max(0.0, 1.0 - ca * ca);
      const double spec = 0.2 + 0.8 * sn2 * sn2 * sn2;  // a cylinder reflects back when the beam is normal to it
      float bf, kf;
      grid_coords(s, t, &bf, &kf);
      const int kk = std::clamp(static_cast<int>(kf), 0, NS_ - 1);
      // per unit length of rod, over the beam spacing; a rod seen end-on still fills its own width
      const double seen = std::max(len / n, 2.0 * rod.radius * (k == 0 ? 1.0 : 0.0));
      float amp = static_cast<float>(kRodGain * rod.reflect * we * spec * seen / std::max(lateral_spacing(kk), 0.5 * px_));
      splat(s, t, amp);
      // comet tail: echoes bouncing inside the rod, one diameter apart along the beam, farther
      const float ds = static_cast<float>(2.0 * rod.radius) * bs, dt = static_cast<float>(2.0 * rod.radius) * bt;
      for (int r = 1; r <= 6; ++r) {
        amp *= rod.reverb;
        s += ds;
        t += dt;
        splat(s, t, amp);
      }
    }
  }
}

void PlaneImager::reverberation() {
  // near-field reverberation: the pulse bouncing between the array's lens and the balloon / rectal
  // wall gives faint bands parallel to the array every lens thickness, fading with each round trip
  constexpr float kLens = 1.1e-3f, kFirst = 0.6f, kRatio = 0.4f;  // [m], [-], [-]
  float amp = kFirst;
  for (int n = 1; n <= 4; ++n, amp *= kRatio) {
    const float kf = n * kLens / static_cast<float>(dz_) - 0.5f;
    const int j = static_cast<int>(kf);
    if (j < 0 || j >= NS_ - 1) break;
    const float v = kf - j;
    for (int b = 0; b < NB_; ++b) {
      const int p0 = samp_pix_[b];  // the array's own sample: no contact, no reverberation
      if (p0 < 0 || img_.label[p0] == 255) continue;
      // a little fixed speckle along the band (the lens is not a perfect mirror)
      const float jitter = 0.75f + 0.5f * static_cast<float>(hash32(static_cast<uint32_t>(b * 7919 + n)) >> 8) * (1.0f / 16777216.0f);
      gre_[static_cast<size_t>(j) * NB_ + b] += amp * jitter * (1 - v) * line_gain_[j];
      gre_[static_cast<size_t>(j + 1) * NB_ + b] += amp * jitter * v * line_gain_[j + 1];
    }
  }
}

void PlaneImager::blur() {
  // axial (between rows), then lateral (along each row, with that depth's kernel)
  convolve_separable(gre_.data(), gtr_.data(), NB_, NS_, kax_.data(), static_cast<int>(kax_.size()), false, pad_.data());
  convolve_separable(gim_.data(), gti_.data(), NB_, NS_, kax_.data(), static_cast<int>(kax_.size()), false, pad_.data());
  for (int k = 0; k < NS_; ++k) {
    const size_t o = static_cast<size_t>(k) * NB_;
    const float* kt = &klat_[klat_off_[k]];
    convolve_row(&gtr_[o], &gre_[o], NB_, kt, klat_r_[k], pad_.data());
    convolve_row(&gti_[o], &gim_[o], NB_, kt, klat_r_[k], pad_.data());
  }
}

void PlaneImager::transmission(const UltrasoundScene& sc, const PlaneFrame& f) {
  for (size_t g : marked_) mark_[g] = 1.0f;  // the entries the last frame's rods marked
  marked_.clear();
  const double r = set_.convex_radius, D = set_.depth, h = 0.5 * set_.fov;
  const double sig_e = set_.slice_thickness / 2.355;
  // rods stop part of the beam that crosses them (seeds, needle: partial shadow). A beam loses
  // the fraction `shadow` x (elevation profile at its closest crossing) once per rod, from the
  // shallowest depth where the rod stops at least 90 % of that: an oblique rod covers several
  // depth samples of one beam, and marking each of them would multiply the loss.
  for (const Rod& rod : sc.rods) {
    const Vec3 da = rod.a - f.origin, db = rod.b - f.origin;
    const double len = (rod.b - rod.a).norm();
    if (!std::isfinite(len) || len <= 0) continue;
    const int n = std::min(20000, static_cast<int>(std::ceil(len / 2.5e-4)));
    // visits the rod's samples seen by the slice: fn(depth sample, transmitted fraction, beams lo..hi)
    auto visit = [&](auto&& fn) {
      for (int k = 0; k <= n; ++k) {
        const double u = static_cast<double>(k) / n;
        const Vec3 q = da + u * (db - da);
        const double e = std::max(0.0, std::abs(q.dot(f.normal)) - rod.radius);
        const double we = std::exp(-0.5 * e * e / (sig_e * sig_e));
        if (we < 0.05) continue;
        const double s = q.dot(f.right), t = q.dot(f.up);
        double bf, depth, half;  // beam index, depth, half-width of the rod in beams
        if (kind_ == PlaneKind::Transverse) {
          const double rho = std::hypot(s, t);
          depth = rho - r;
          bf = (std::atan2(s, t) + h) / dbeam_ - 0.5;
          half = rod.radius / std::max(rho, 1e-4) / dbeam_;
        } else {
          depth = t - r;
          bf = (s + 0.5 * set_.linear_width) / dbeam_ - 0.5;
          half = rod.radius / dbeam_;
        }
        const int kk = static_cast<int>(std::floor(depth / D * NS_));
        if (kk < 0 || kk >= NS_) continue;
        const int lo = std::max(0, static_cast<int>(std::floor(bf - half))), hi = std::min(NB_ - 1, static_cast<int>(std::ceil(bf + half)));
        fn(kk, static_cast<float>(1.0 - rod.shadow * we), lo, hi);
      }
    };
    std::fill(rod_k_.begin(), rod_k_.end(), NS_);
    std::fill(rod_m_.begin(), rod_m_.end(), 1.0f);
    visit([&](int, float m, int lo, int hi) {
      for (int b = lo; b <= hi; ++b) rod_m_[b] = std::min(rod_m_[b], m);
    });
    visit([&](int kk, float m, int lo, int hi) {
      for (int b = lo; b <= hi; ++b)
        if (m <= 1.0f - 0.9f * (1.0f - rod_m_[b])) rod_k_[b] = std::min(rod_k_[b], kk);
    });
    // the echo of the rod's own depth sample stays; the shadow starts one resolution cell below
    const int below = std::max(1, static_cast<int>(std::ceil(psf_axial_fwhm() / dz_)));
    for (int b = 0; b < NB_; ++b)
      if (rod_k_[b] + below < NS_) {
        const size_t g = static_cast<size_t>(rod_k_[b] + below) * NB_ + b;
        if (mark_[g] == 1.0f && rod_m_[b] != 1.0f) marked_.push_back(g);
        mark_[g] *= rod_m_[b];  // rods in a row: each stops its part
      }
  }
  // round-trip attenuation factor of one sample step, per label
  float fac[128 + 1];
  const double step_cm = dz_ * 100.0, f_mhz = set_.frequency * 1e-6;
  auto factor = [&](double alpha) { return static_cast<float>(std::pow(10.0, -2.0 * alpha * f_mhz * step_cm / 20.0)); };
  const float soft = factor(acoustics(Tissue::Soft).atten);
  for (int l = 0; l <= 128; ++l) fac[l] = soft;
  for (size_t c = 0; c < an_.components.size(); ++c) fac[c] = factor(acoustics(an_.components[c].tissue).atten);
  // calcifications (prostate echo volume above kCalcEcho) stop the beam like bone
  const float calc = factor(acoustics(Tissue::Bone).atten);
  // row by row (contiguous in memory), each beam's running product in beam_T_: T(k) is the product
  // of the factors of the samples above k, in depth order
  const int NB = NB_, NS = NS_;
  const uint8_t* const glab = glab_.data();  // the label of each sample (scatter())
  const uint8_t* const stop = stop_.data();
  const float* const mark = mark_.data();
  float* const Tb = beam_T_.data();
  std::fill(Tb, Tb + NB, 1.0f);
  // each echo source x the round trip to it, before the pulse spreads it (blur()): a reflector's
  // echo keeps its whole pulse length, the part behind a bone surface included, and a shadow's
  // edges are as soft as the beam is wide
  float* const gre = gre_.data();
  float* const gim = gim_.data();
  for (int k = 0; k < NS; ++k)
    for (int b = 0; b < NB; ++b) {
      const size_t g = static_cast<size_t>(k) * NB + b;
      gre[g] *= Tb[b];
      gim[g] *= Tb[b];
      const uint8_t lab = glab[g];
      float a = lab == 255 ? soft : fac[lab >= 64 ? 128 : lab];
      if (stop[g]) a = calc;
      Tb[b] *= a * mark[g];
    }
}

void PlaneImager::calibrate() {
  // the I/Q signal x the speckle calibration of its depth, scan-converted before detection
  // (compress())
  for (int k = 0; k < NS_; ++k)
    for (int b = 0; b < NB_; ++b) {
      const size_t g = static_cast<size_t>(k) * NB_ + b;
      eq_[2 * g] = gre_[g] * calib_[k];
      eq_[2 * g + 1] = gim_[g] * calib_[k];
    }
}

void PlaneImager::compress() {
  const float dr = static_cast<float>(set_.dynamic_range_db);
  // gray = 255 * (20 log10(env) / DR + floor); 20 log10(x) = 6.0206 log2(x)
  const float a = 255.0f * 6.0205999f / dr, b0 = 255.0f * kDisplayFloor;
  const size_t nv = view_pix_.size();
  compress_run(eq_.data(), NB_, sub_, sub_w_.data(), tgc_v_.data(), lut_i_.data(), lut_wb_.data(), lut_wk_.data(), a, b0,
               env_v_.data(), gray_.data(), mag2_.data(), pix_v_.data(), nv);
  // into the image; the pixels outside the view stay 0 from the constructor
  for (size_t v = 0; v < nv; ++v) {
    img_.envelope[view_pix_[v]] = env_v_[v];
    img_.pixels[view_pix_[v]] = pix_v_[v];
  }
}

void PlaneImager::overlays(const UltrasoundScene& sc, const PlaneFrame& f) {
  if (!set_.overlays) return;
  auto dot = [&](double col, double row, int r, uint8_t v) {
    const int ci = static_cast<int>(std::lround(col)), rj = static_cast<int>(std::lround(row));
    for (int j = rj - r; j <= rj + r; ++j)
      for (int i = ci - r; i <= ci + r; ++i)
        if (i >= 0 && j >= 0 && i < W_ && j < H_ && img_.in_view[static_cast<size_t>(j) * W_ + i])
          img_.pixels[static_cast<size_t>(j) * W_ + i] = v;
  };
  for (const OverlayLine& o : sc.overlays) {
    const Vec3 d0 = o.entry - f.origin;
    if (o.kind == OverlayLine::Guide) {
      // dotted line in the plane it lies in: a dot per 2.5 mm, a bigger one per centimetre
      for (int k = 0; k <= 60; ++k) {
        const Vec3 q = d0 + (k * 2.5e-3) * o.direction;
        if (std::abs(q.dot(f.normal)) > set_.slice_thickness) continue;
        dot((q.dot(f.right) - s0_) / px_, (t0_ - q.dot(f.up)) / px_, k % 4 == 0 ? 2 : 1, 230);
      }
    } else {
      const double dn = o.direction.dot(f.normal);
      if (std::abs(dn) < 1e-6) continue;
      const Vec3 q = d0 - (d0.dot(f.normal) / dn) * o.direction;
      const double col = (q.dot(f.right) - s0_) / px_, row = (t0_ - q.dot(f.up)) / px_;
      dot(col, row, 0, 210);
      dot(col - 1, row, 0, 210);
      dot(col + 1, row, 0, 210);
      dot(col, row - 1, 0, 210);
      dot(col, row + 1, 0, 210);
    }
  }
  // fused MRI contours: where each lesion's sphere (rest extent, current centroid) cuts the plane,
  // a dashed circle
  if (!set_.lesion_contours || !sc.x) return;
  for (const UsLesion& l : an_.lesions) {
    Vec3 c = Vec3::Zero();
    for (int p : l.particles) c += Vec3(sc.x[3 * p], sc.x[3 * p + 1], sc.x[3 * p + 2]);
    c /= static_cast<double>(l.particles.size());
    const Vec3 d0 = c - f.origin;
    const double h = d0.dot(f.normal);
    if (std::abs(h) >= l.radius) continue;
    const double r = std::sqrt(l.radius * l.radius - h * h);
    const double col0 = (d0.dot(f.right) - s0_) / px_, row0 = (t0_ - d0.dot(f.up)) / px_;
    const int n = std::max(24, static_cast<int>(2.0 * 3.141592653589793 * r / px_));
    for (int k = 0; k < n; ++k) {
      if ((k * 12 / n) % 2) continue;  // 6 dashes
      const double a = 2.0 * 3.141592653589793 * k / n;
      dot(col0 + r * std::cos(a) / px_, row0 - r * std::sin(a) / px_, 0, 255);
    }
  }
}

}  // namespace ps::us
