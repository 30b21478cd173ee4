#include "engine/ultrasound/imager.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "engine/ultrasound/speckle.h"
#include "engine/util/multiversion.h"
#include "engine/ultrasound/speckle_row.h"

namespace ps::us {

namespace {

constexpr double kPi = 3.141592653589793;
constexpr float kDisplayFloor = 0.4f;     // unit-backscatter speckle rms at 40 % of the dynamic range
constexpr float kTextureScale = 3.0e-3f;  // heterogeneity lattice (fat lobules, nodules) [m]
constexpr double kGridStep = 2.0e-3;      // displacement grid [m]
// Speckle lattice step in pixels. The scatterer field must be smooth on the pixel scale, else a
// sub-pixel tissue motion samples different scatterers and the speckle decorrelates (flickers):
// measured with the block-matching test, a 0.6 px lattice gave a peak NCC of 0.27 after a 0.73 mm
// shift, 1.5 px gives > 0.9 (docs/ultrasound.md).
constexpr double kLatticePixels = 1.5;
// A fixed generic rotation of rest space before the lattice, so that no anatomical plane (the
// transverse plane is often z = const) cuts the lattice along its axes (a visible square grid).
constexpr float kRot[9] = {0.8660254f, -0.3535534f, 0.3535534f, 0.0f, 0.7071068f, 0.7071068f, -0.5f, -0.6123724f, 0.6123724f};
constexpr int kBeams = 192, kSamples = 256;  // propagation grid
constexpr int kTexStep = 4;               // heterogeneity texture evaluated every 4 pixels

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


// log compression of one run of pixels (compress()): envelope |re + i im| x transmission x TGC,
// then gray = a log2(env) + b0 on [0, 255]; outside the view 0. Built like convolve().
PS_TARGET_CLONES("avx2", "default") PS_OPTIMIZE_O3
void compress_run(const float* re, const float* im, const float* tgc, const int* lut_i, const float* lut_wb, const float* lut_wk,
                  const uint8_t* in_view, const float* T, int NS, float a, float b0, float* envelope, uint8_t* pixels, size_t n) {
  for (size_t p = 0; p < n; ++p) {
    const int i = in_view[p] ? lut_i[p] : 0;
    const float wb = lut_wb[p], wk = lut_wk[p];
    const float Tp = (1 - wb) * ((1 - wk) * T[i] + wk * T[i + 1]) + wb * ((1 - wk) * T[i + NS] + wk * T[i + NS + 1]);
    float env = std::sqrt(re[p] * re[p] + im[p] * im[p]) * Tp * tgc[p];
    env = in_view[p] ? env : 0.0f;
    envelope[p] = env;
    const float g = env > 1e-12f ? a * fast_log2(env) + b0 : 0.0f;
    pixels[p] = static_cast<uint8_t>(std::clamp(g, 0.0f, 255.0f));
  }
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
  lut_i_.assign(np, -1);
  lut_wb_.assign(np, 0.0f);
  lut_wk_.assign(np, 0.0f);
  mask_.assign(np, 0);
  cre_.assign(np, 0.0f);
  cim_.assign(np, 0.0f);
  tmp_re_.assign(np, 0.0f);
  tmp_im_.assign(np, 0.0f);

  NB_ = kind_ == PlaneKind::Transverse ? kBeams : kBeams * 2 / 3;
  NS_ = kSamples;
  const double f_mhz = set_.frequency * 1e-6;
  for (int j = 0; j < H_; ++j)
    for (int i = 0; i < W_; ++i) {
      const double s = pixel_s(i), t = pixel_t(j);
      double depth = -1.0, bf = 0.0;
      if (kind_ == PlaneKind::Transverse) {
        const double rho = std::hypot(s, t), phi = std::atan2(s, t);
        if (rho >= r && rho <= R && std::abs(phi) <= h) depth = rho - r, bf = (phi + h) / (2 * h) * NB_ - 0.5;
      } else if (std::abs(s) <= 0.5 * set_.linear_width && t >= r && t <= R) {
        depth = t - r, bf = (s + 0.5 * set_.linear_width) / set_.linear_width * NB_ - 0.5;
      }
      if (depth < 0) continue;
      const size_t p = static_cast<size_t>(j) * W_ + i;
      img_.in_view[p] = 1;
      depth_[p] = static_cast<float>(depth);
      const double kf = depth / D * NS_ - 0.5;
      const double bc = std::clamp(bf, 0.0, NB_ - 1.000001), kc = std::clamp(kf, 0.0, NS_ - 1.000001);
      const int b0 = std::min(static_cast<int>(bc), NB_ - 2), k0 = std::min(static_cast<int>(kc), NS_ - 2);
      lut_i_[p] = b0 * NS_ + k0;
      lut_wb_[p] = static_cast<float>(bc - b0);
      lut_wk_[p] = static_cast<float>(kc - k0);
      // round-trip TGC in dB: 2 * slope * f * depth
      const double tgc_db = 2.0 * set_.tgc_db_cm_mhz * f_mhz * depth * 100.0 + set_.gain_db;
      tgc_[p] = static_cast<float>(std::pow(10.0, tgc_db / 20.0));
    }
  beam_pix_.assign(static_cast<size_t>(NB_) * NS_, -1);
  T_.assign(beam_pix_.size(), 1.0f);
  mark_.assign(beam_pix_.size(), 1.0f);
  rod_k_.assign(NB_, NS_);
  rod_m_.assign(NB_, 1.0f);
  for (int b = 0; b < NB_; ++b)
    for (int k = 0; k < NS_; ++k) {
      double s, t;
      const double rho = r + (k + 0.5) * D / NS_;
      if (kind_ == PlaneKind::Transverse) {
        const double phi = -h + (b + 0.5) * 2 * h / NB_;
        s = rho * std::sin(phi), t = rho * std::cos(phi);
      } else {
        s = -0.5 * set_.linear_width + (b + 0.5) * set_.linear_width / NB_, t = rho;
      }
      const int i = static_cast<int>(std::lround((s - s0_) / px_)), j = static_cast<int>(std::lround((t0_ - t) / px_));
      if (i >= 0 && i < W_ && j >= 0 && j < H_) beam_pix_[static_cast<size_t>(b) * NS_ + k] = j * W_ + i;
    }

  // point-spread function: axial FWHM ~1.5 wavelengths (two-cycle pulse), lateral FWHM ~3.5
  // wavelengths (f-number ~3.5), never narrower than the pixels (else the speckle aliases and
  // flickers as the tissue moves)
  const double lambda = wavelength();
  const double sig_ax = std::max(1.5 * lambda / 2.355 / px_, 1.2);
  const double sig_lat = std::max(3.5 * lambda / 2.355 / px_, 2.0);
  kax_ = gaussian_taps(sig_ax);
  klat_ = gaussian_taps(sig_lat);
  pad_.assign(W_ + klat_.size(), 0.0f);
  row_q_.assign(6 * static_cast<size_t>(W_), 0.0f);
  row_i_.assign(W_, 0);
  lattice_ = static_cast<float>(kLatticePixels * px_);

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
  // per pixel column: its displacement-grid cell and weight (the same for every row), as scatter()
  // computed them per pixel
  col_a_.assign(W_, 0);
  col_wa_.assign(W_, 0.0f);
  for (int i = 0; i < W_; ++i) {
    const float s = static_cast<float>(pixel_s(i));
    const float afx = (s - static_cast<float>(gs0_)) * static_cast<float>(1.0 / g_);
    col_a_[i] = std::clamp(static_cast<int>(afx), 0, gx_ - 2);
    col_wa_[i] = std::clamp(afx - col_a_[i], 0.0f, 1.0f);
  }
  for (const UsComponent& c : an_.components) {
    comp_ac_.push_back(acoustics(c.tissue));
    comp_prostate_.push_back(c.tissue == Tissue::Prostate ? 1 : 0);
  }
  rank_comp_.assign(32, 0);
  for (int c = 0; c < nc; ++c) rank_comp_[an_.components[c].priority] = c;
  rest_.resize(3 * an_.rest.size());
  for (size_t p = 0; p < an_.rest.size(); ++p)
    for (int d = 0; d < 3; ++d) rest_[3 * p + d] = static_cast<float>(an_.rest[p][d]);
  ps_.assign(an_.rest.size(), 0.0f);
  pt_.assign(an_.rest.size(), 0.0f);
  pe_.assign(an_.rest.size(), 0.0f);
  size_t faces = 0;
  for (const auto& c : an_.components) faces += c.faces.size();
  segs_.reserve(faces);

  // reference amplitude: rms envelope of unit-backscatter speckle through this PSF, measured on a
  // patch cut obliquely through the lattice (deterministic)
  {
    const int n = 96;
    std::vector<float> re(n * n), im(n * n), tr(n * n), ti(n * n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double q = 1.0 / kLatticePixels;  // one pixel in lattice units, along two rotated axes
        const float x = static_cast<float>(q * (i * kRot[0] + j * kRot[1])), y = static_cast<float>(q * (i * kRot[3] + j * kRot[4])),
                    z = static_cast<float>(q * (i * kRot[6] + j * kRot[7]));
        speckle_noise(x + 1000.3f, y + 2000.7f, z + 3000.1f, re[j * n + i], im[j * n + i]);
      }
    std::vector<float> pad(n + klat_.size());
    convolve_separable(re.data(), tr.data(), n, n, klat_.data(), int(klat_.size()), true, pad.data());
    convolve_separable(im.data(), ti.data(), n, n, klat_.data(), int(klat_.size()), true, pad.data());
    convolve_separable(tr.data(), re.data(), n, n, kax_.data(), int(kax_.size()), false, pad.data());
    convolve_separable(ti.data(), im.data(), n, n, kax_.data(), int(kax_.size()), false, pad.data());
    double sum = 0.0;
    int cnt = 0;
    for (int j = 16; j < n - 16; ++j)
      for (int i = 16; i < n - 16; ++i, ++cnt) sum += re[j * n + i] * re[j * n + i] + im[j * n + i] * im[j * n + i];
    ref_ = static_cast<float>(std::sqrt(sum / cnt));
  }
  for (float& t : tgc_) t /= ref_;
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
  for (int p = 0; p < sc.particle_count; ++p) {
    const float d0 = sc.x[3 * p] - O[0], d1 = sc.x[3 * p + 1] - O[1], d2 = sc.x[3 * p + 2] - O[2];
    ps_[p] = d0 * Rr[0] + d1 * Rr[1] + d2 * Rr[2];
    pt_[p] = d0 * Ru[0] + d1 * Ru[1] + d2 * Ru[2];
    pe_[p] = d0 * Rn[0] + d1 * Rn[1] + d2 * Rn[2];
  }
  cut_surfaces(sc, f);
  fill_labels();
  wall_bands();
  displacement_fields(sc, f);
  scatter(f);
  coherent_surfaces();
  coherent_rods(sc, f);
  blur();
  transmission(sc, f);
  compress();
  overlays(sc, f);
  return img_;
}

void PlaneImager::cut_surfaces(const UltrasoundScene& sc, const PlaneFrame& f) {
  segs_.clear();
  const float* x = sc.x;
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
      for (int d = 0; d < 3; ++d) {
        a1[d] = x[3 * v[1] + d] - x[3 * v[0] + d];
        a2[d] = x[3 * v[2] + d] - x[3 * v[0] + d];
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

void PlaneImager::scatter(const PlaneFrame& f) {
  const size_t nodes = static_cast<size_t>(gx_) * gy_;
  const float invL = 1.0f / lattice_, invT = 1.0f / kTextureScale;
  const RestVolume& vol = an_.prostate_echo;
  const float vinv = static_cast<float>(1.0 / vol.step);
  const float vo[3] = {float(vol.origin.x()), float(vol.origin.y()), float(vol.origin.z())};
  const float pxf = static_cast<float>(px_);
  const float inv_g = static_cast<float>(1.0 / g_);
  // texture at the coarse nodes (every kTexStep pixels), at the rest point of the mean field
  const float* all = &field_[an_.components.size() * nodes * 4];
  for (int tb = 0; tb < ty_; ++tb)
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
      tex_[static_cast<size_t>(tb) * tx_ + ta] = texture_noise(X[0] * invT, X[1] * invT, X[2] * invT);
    }
  for (int j = 0; j < H_; ++j) {
    const float wtex = static_cast<float>(j % kTexStep) * (1.0f / kTexStep);
    const float t = static_cast<float>(pixel_t(j));
    const float bfy = (static_cast<float>(gt0_) - t) * inv_g;
    const int b = std::clamp(static_cast<int>(bfy), 0, gy_ - 2);
    const float wb = std::clamp(bfy - b, 0.0f, 1.0f);
    const Vec3 row0 = f.origin + pixel_s(0) * f.right + static_cast<double>(t) * f.up;
    const float x0[3] = {float(row0.x()), float(row0.y()), float(row0.z())};
    const float dr[3] = {float(f.right.x()) * pxf, float(f.right.y()) * pxf, float(f.right.z()) * pxf};
    int na = 0;  // active pixels of this row, compacted for the vectorised noise kernel
    for (int i = 0; i < W_; ++i) {
      const size_t p = static_cast<size_t>(j) * W_ + i;
      cre_[p] = cim_[p] = 0.0f;
      const uint8_t lab = img_.label[p];
      if (!img_.in_view[p] || lab == 255) continue;
      const int c = lab & 63;
      const TissueAcoustics& ac = comp_ac_[c];
      const bool wall = lab >= 64;
      const bool prostate = comp_prostate_[c] != 0;
      float echo = wall ? ac.wall_echo : ac.echo;
      if (echo <= 0.0f && !prostate) continue;
      const int a = col_a_[i];     // displacement-grid column of pixel column i (fixed)
      const float wa = col_wa_[i];
      const float* fc = &field_[static_cast<size_t>(c) * nodes * 4];
      const float* n00 = &fc[(static_cast<size_t>(b) * gx_ + a) * 4];
      const float* n10 = n00 + 4;
      const float* n01 = n00 + static_cast<size_t>(gx_) * 4;
      const float* n11 = n01 + 4;
      const float w00 = (1 - wa) * (1 - wb), w10 = wa * (1 - wb), w01 = (1 - wa) * wb, w11 = wa * wb;
      float X[3];
      for (int d = 0; d < 3; ++d)
        X[d] = x0[d] + i * dr[d] - (w00 * n00[d] + w10 * n10[d] + w01 * n01[d] + w11 * n11[d]);
      if (!wall && prostate && !vol.empty()) {
        // trilinear look-up of the rest-space echo volume (zones, lesion, urethra)
        const float qx = (X[0] - vo[0]) * vinv, qy = (X[1] - vo[1]) * vinv, qz = (X[2] - vo[2]) * vinv;
        if (qx >= 0 && qy >= 0 && qz >= 0 && qx < vol.nx - 1 && qy < vol.ny - 1 && qz < vol.nz - 1) {
          const int ix = static_cast<int>(qx), iy = static_cast<int>(qy), iz = static_cast<int>(qz);
          const float u = qx - ix, v = qy - iy, w = qz - iz;
          const float* e0 = &vol.value[(static_cast<size_t>(iz) * vol.ny + iy) * vol.nx + ix];
          const float* e1 = e0 + static_cast<size_t>(vol.nx) * vol.ny;
          const int sx = 1, sy = vol.nx;
          const float c0 = (e0[0] * (1 - u) + e0[sx] * u) * (1 - v) + (e0[sy] * (1 - u) + e0[sy + sx] * u) * v;
          const float c1 = (e1[0] * (1 - u) + e1[sx] * u) * (1 - v) + (e1[sy] * (1 - u) + e1[sy + sx] * u) * v;
          echo = c0 * (1 - w) + c1 * w;
        }
      }
      if (!wall && ac.hetero > 0.0f) {
        // low-frequency texture from the coarse grid (bilinear; it varies over ~3 mm)
        const int ta = i / kTexStep, tb = j / kTexStep;
        const float tu = static_cast<float>(i - ta * kTexStep) * (1.0f / kTexStep), tv = wtex;
        const float* q = &tex_[static_cast<size_t>(tb) * tx_ + ta];
        const float tval = (q[0] * (1 - tu) + q[1] * tu) * (1 - tv) + (q[tx_] * (1 - tu) + q[tx_ + 1] * tu) * tv;
        echo *= std::max(0.05f, 1.0f + ac.hetero * (2.0f * tval - 1.0f));
      }
      if (echo <= 0.0f) continue;
      row_i_[na] = i;
      row_q_[na] = (kRot[0] * X[0] + kRot[1] * X[1] + kRot[2] * X[2]) * invL;
      row_q_[W_ + na] = (kRot[3] * X[0] + kRot[4] * X[1] + kRot[5] * X[2]) * invL;
      row_q_[2 * W_ + na] = (kRot[6] * X[0] + kRot[7] * X[1] + kRot[8] * X[2]) * invL;
      row_q_[3 * W_ + na] = echo;
      ++na;
    }
    float* re = &row_q_[4 * static_cast<size_t>(W_)];
    float* im = &row_q_[5 * static_cast<size_t>(W_)];
    speckle_row(&row_q_[0], &row_q_[W_], &row_q_[2 * static_cast<size_t>(W_)], &row_q_[3 * static_cast<size_t>(W_)], re, im, na);
    float* cr = &cre_[static_cast<size_t>(j) * W_];
    float* ci = &cim_[static_cast<size_t>(j) * W_];
    for (int a = 0; a < na; ++a) cr[row_i_[a]] = re[a], ci[row_i_[a]] = im[a];
  }
}

void PlaneImager::splat(float col, float row, float amp) {
  const int i = static_cast<int>(std::floor(col)), j = static_cast<int>(std::floor(row));
  if (i < 0 || j < 0 || i >= W_ - 1 || j >= H_ - 1) return;
  const float u = col - i, v = row - j;
  const size_t p = static_cast<size_t>(j) * W_ + i;
  cre_[p] += amp * (1 - u) * (1 - v);
  cre_[p + 1] += amp * u * (1 - v);
  cre_[p + W_] += amp * (1 - u) * v;
  cre_[p + W_ + 1] += amp * u * v;
}

void PlaneImager::coherent_surfaces() {
  // a line of density A (per pixel of length) blurs to a peak of A * kax[centre]: scale so that an
  // interface of reflection 1 peaks at the unit-backscatter speckle rms
  const float line_gain = ref_ / kax_[kax_.size() / 2];
  const float inv = static_cast<float>(1.0 / px_);
  for (const Seg& s : segs_) {
    const TissueAcoustics& ac = acoustics(an_.components[s.comp].tissue);
    if (ac.interface <= 0.0f && ac.diffuse <= 0.0f) continue;
    float bs, bt;
    beam_dir(0.5f * (s.s0 + s.s1), 0.5f * (s.t0 + s.t1), &bs, &bt);
    const float c = std::abs(s.nr * bs + s.nu * bt);  // cosine of the angle of incidence
    const float c2 = c * c;
    const float amp = (ac.interface * c2 * c2 + ac.diffuse) * line_gain;
    const float x0 = (s.s0 - static_cast<float>(s0_)) * inv, y0 = (static_cast<float>(t0_) - s.t0) * inv;
    const float x1 = (s.s1 - static_cast<float>(s0_)) * inv, y1 = (static_cast<float>(t0_) - s.t1) * inv;
    const float len = std::sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0));
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.5f)));
    const float step = len / n;
    for (int k = 0; k < n; ++k) {
      const float u = (k + 0.5f) / n;
      splat(x0 + u * (x1 - x0), y0 + u * (y1 - y0), amp * step);
    }
  }
}

void PlaneImager::coherent_rods(const UltrasoundScene& sc, const PlaneFrame& f) {
  const float line_gain = ref_ / kax_[kax_.size() / 2];
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
      const float s = static_cast<float>(sa + u * (sb - sa)), t = static_cast<float>(ta + u * (tb - ta));
      float bs, bt;
      beam_dir(s, t, &bs, &bt);
      const double ca = ar * bs + au * bt;          // cosine between the rod axis and the beam
      const double sn2 = std::max(0.0, 1.0 - ca * ca);
      const double spec = 0.2 + 0.8 * sn2 * sn2 * sn2;  // a cylinder reflects back when the beam is normal to it
      float amp = static_cast<float>(rod.reflect * we * spec * (len / n / px_)) * line_gain;
      float col = static_cast<float>((s - s0_) / px_), row = static_cast<float>((t0_ - t) / px_);
      splat(col, row, amp);
      // comet tail: echoes bouncing inside the rod, one diameter apart along the beam, farther
      const float dcol = static_cast<float>(2.0 * rod.radius / px_ * bs), drow = static_cast<float>(-2.0 * rod.radius / px_ * bt);
      for (int r = 1; r <= 6; ++r) {
        amp *= rod.reverb;
        col += dcol;
        row += drow;
        splat(col, row, amp);
      }
    }
  }
}

void PlaneImager::blur() {
  const int nl = static_cast<int>(klat_.size()), na = static_cast<int>(kax_.size());
  convolve_separable(cre_.data(), tmp_re_.data(), W_, H_, klat_.data(), nl, true, pad_.data());
  convolve_separable(cim_.data(), tmp_im_.data(), W_, H_, klat_.data(), nl, true, pad_.data());
  convolve_separable(tmp_re_.data(), cre_.data(), W_, H_, kax_.data(), na, false, pad_.data());
  convolve_separable(tmp_im_.data(), cim_.data(), W_, H_, kax_.data(), na, false, pad_.data());
}

void PlaneImager::transmission(const UltrasoundScene& sc, const PlaneFrame& f) {
  std::fill(mark_.begin(), mark_.end(), 1.0f);
  const double r = set_.convex_radius, D = set_.depth, h = 0.5 * set_.fov;
  const double sig_e = set_.slice_thickness / 2.355;
  // rods stop part of the beam that crosses them (seeds, needle: partial shadow). A beam loses
  // the fraction `shadow` x (elevation profile at its closest crossing) once per rod, from the
  // shallowest depth where the rod stops at least 90 % of that. A rod oblique to the beams covers
  // several depth cells of one beam: marking each of them multiplied the loss (0.6^5 = -22 dB
  // behind the 25 deg biopsy needle in the sagittal plane instead of -4.4 dB, a dark band over the
  // gland); taking the shallowest cell of any weight shadowed a needle crossing the transverse
  // plane obliquely before its own in-plane echo.
  for (const Rod& rod : sc.rods) {
    const Vec3 da = rod.a - f.origin, db = rod.b - f.origin;
    const double len = (rod.b - rod.a).norm();
    if (!std::isfinite(len) || len <= 0) continue;
    const int n = std::min(20000, static_cast<int>(std::ceil(len / 2.5e-4)));
    // visits the rod's samples seen by the slice: fn(depth cell, transmitted fraction, beams lo..hi)
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
          bf = (std::atan2(s, t) + h) / (2 * h) * NB_ - 0.5;
          half = rod.radius / std::max(rho, 1e-4) / (2 * h / NB_);
        } else {
          depth = t - r;
          bf = (s + 0.5 * set_.linear_width) / set_.linear_width * NB_ - 0.5;
          half = rod.radius / (set_.linear_width / NB_);
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
    for (int b = 0; b < NB_; ++b)
      if (rod_k_[b] < NS_) mark_[static_cast<size_t>(b) * NS_ + rod_k_[b]] *= rod_m_[b];  // rods in a row: each stops its part
  }
  // round-trip attenuation factor of one sample step, per label
  float fac[128 + 1];
  const double step_cm = D / NS_ * 100.0, f_mhz = set_.frequency * 1e-6;
  auto factor = [&](double alpha) { return static_cast<float>(std::pow(10.0, -2.0 * alpha * f_mhz * step_cm / 20.0)); };
  const float soft = factor(0.6);
  for (int l = 0; l <= 128; ++l) fac[l] = soft;
  for (size_t c = 0; c < an_.components.size(); ++c) fac[c] = factor(acoustics(an_.components[c].tissue).atten);
  for (int b = 0; b < NB_; ++b) {
    float T = 1.0f;
    const size_t row = static_cast<size_t>(b) * NS_;
    for (int k = 0; k < NS_; ++k) {
      T_[row + k] = T;
      const int p = beam_pix_[row + k];
      const uint8_t lab = p >= 0 ? img_.label[p] : uint8_t{255};
      T *= (lab == 255 ? soft : fac[lab >= 64 ? 128 : lab]) * mark_[row + k];
    }
  }
}

void PlaneImager::compress() {
  const float dr = static_cast<float>(set_.dynamic_range_db);
  // gray = 255 * (20 log10(env) / DR + floor); 20 log10(x) = 6.0206 log2(x)
  const float a = 255.0f * 6.0205999f / dr, b0 = 255.0f * kDisplayFloor;
  const size_t np = static_cast<size_t>(W_) * H_;
  compress_run(cre_.data(), cim_.data(), tgc_.data(), lut_i_.data(), lut_wb_.data(), lut_wk_.data(), img_.in_view.data(), T_.data(), NS_,
               a, b0, img_.envelope.data(), img_.pixels.data(), np);
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
