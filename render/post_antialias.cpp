#include "render/post_antialias.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ps::render {

bool parse_antialias(const std::string& s, Antialias& out) {
  for (Antialias a : {Antialias::Auto, Antialias::Msaa, Antialias::Fxaa, Antialias::None})
    if (s == antialias_name(a)) {
      out = a;
      return true;
    }
  return false;
}

const char* antialias_name(Antialias a) {
  switch (a) {
    case Antialias::Auto: return "auto";
    case Antialias::Msaa: return "msaa";
    case Antialias::Fxaa: return "fxaa";
    case Antialias::None: return "none";
  }
  return "?";
}

bool is_software_renderer(const std::string& r) {
  for (const char* w : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer"})
    if (r.find(w) != std::string::npos) return true;
  return false;
}

Antialias resolve_antialias(Antialias a, const std::string& gl_renderer) {
  if (a != Antialias::Auto) return a;
  return is_software_renderer(gl_renderer) ? Antialias::Fxaa : Antialias::Msaa;
}

namespace {

// Rec. 601 luma in 0..255, as the integer weights 77 + 150 + 29 = 256
inline uint8_t luma_of(const uint8_t* p) { return static_cast<uint8_t>((77 * p[0] + 150 * p[1] + 29 * p[2] + 128) >> 8); }

// Bilinear sampling at (x, y) in pixel units, pixel centres at integers, clamped to the image.
struct Sampler {
  int w, h;
  void at(float& x, float& y, size_t i[4], float& ax, float& ay) const {
    x = std::clamp(x, 0.0f, static_cast<float>(w - 1));
    y = std::clamp(y, 0.0f, static_cast<float>(h - 1));
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    ax = x - static_cast<float>(x0);
    ay = y - static_cast<float>(y0);
    i[0] = static_cast<size_t>(y0) * w + x0;
    i[1] = static_cast<size_t>(y0) * w + x1;
    i[2] = static_cast<size_t>(y1) * w + x0;
    i[3] = static_cast<size_t>(y1) * w + x1;
  }
  float luma(const uint8_t* l, float x, float y) const {
    size_t i[4];
    float ax, ay;
    at(x, y, i, ax, ay);
    const float a = l[i[0]], b = l[i[1]], c = l[i[2]], d = l[i[3]];
    const float top = a + ax * (b - a), bottom = c + ax * (d - c);
    return top + ay * (bottom - top);
  }
  void rgb(const uint8_t* px, float x, float y, uint8_t out[3]) const {
    size_t i[4];
    float ax, ay;
    at(x, y, i, ax, ay);
    for (int k = 0; k < 3; ++k) {
      const float a = px[3 * i[0] + k], b = px[3 * i[1] + k], c = px[3 * i[2] + k], d = px[3 * i[3] + k];
      const float top = a + ax * (b - a), bottom = c + ax * (d - c);
      out[k] = static_cast<uint8_t>(std::clamp(std::lround(top + ay * (bottom - top)), 0L, 255L));
    }
  }
};

constexpr int kThresholdMin = 16;          // absolute contrast, 1/16 of full scale (dark regions)
constexpr int kThresholdShift = 3;         // contrast relative to the local maximum: 1/8
constexpr float kSubpix = 0.25f;           // sub-pixel aliasing removal (0 off, 1 softest)
constexpr float kSteps[] = {1.0f, 1.5f, 2.0f, 2.0f, 2.0f, 2.0f, 4.0f, 8.0f};  // edge search [px]

// Whether pixel x of a row has contrast enough to be an edge: its luma and its 4 neighbours'
// (rows n, c, s; columns clamped at the image's sides) span at least max(16, max / 8).
inline bool is_edge(const uint8_t* rn, const uint8_t* rc, const uint8_t* rs, int xw, int x, int xe) {
  const int hi = std::max(std::max(std::max(rn[x], rs[x]), std::max(rc[xw], rc[xe])), rc[x]);
  const int lo = std::min(std::min(std::min(rn[x], rs[x]), std::min(rc[xw], rc[xe])), rc[x]);
  return hi - lo >= std::max(kThresholdMin, hi >> kThresholdShift);
}

// The FXAA resample of one edge pixel (x, y) into out[3].
void resample(const uint8_t* src, const uint8_t* L, const Sampler& smp, const uint8_t* rn, const uint8_t* rc,
              const uint8_t* rs, int xw, int x, int xe, int y, uint8_t out[3]) {
  const float m = rc[x];
  float ln = rn[x], ls = rs[x];
  const float lw = rc[xw], le = rc[xe];
  const float lmax = std::max(std::max(std::max(ln, ls), std::max(lw, le)), m);
  const float lmin = std::min(std::min(std::min(ln, ls), std::min(lw, le)), m);
  const float range = lmax - lmin;
  const float lnw = rn[xw], lne = rn[xe], lsw = rs[xw], lse = rs[xe];
  // which way the edge runs: second differences across rows against across columns
  const float edge_horz = std::fabs(-2.0f * lw + lnw + lsw) + 2.0f * std::fabs(-2.0f * m + ln + ls) +
                          std::fabs(-2.0f * le + lne + lse);
  const float edge_vert = std::fabs(-2.0f * ls + lsw + lse) + 2.0f * std::fabs(-2.0f * m + lw + le) +
                          std::fabs(-2.0f * ln + lnw + lne);
  const bool horz = edge_horz >= edge_vert;  // edge along x: search along x, shift in y
  // sub-pixel aliasing: how far the pixel stands out from its 3x3 neighbourhood's mean
  const float mean = (2.0f * (ln + ls + lw + le) + lnw + lne + lsw + lse) / 12.0f;
  const float subc = std::clamp(std::fabs(mean - m) / range, 0.0f, 1.0f);
  const float subf = (-2.0f * subc + 3.0f) * subc * subc;
  const float sub_offset = subf * subf * kSubpix;
  if (!horz) {
    ln = lw;
    ls = le;
  }
  // the side of the edge: the neighbour across it with the larger step
  const float gn = ln - m, gs = ls - m;
  const bool pair_n = std::fabs(gn) >= std::fabs(gs);
  const float gradient = std::max(std::fabs(gn), std::fabs(gs));
  const float sign = pair_n ? -1.0f : 1.0f;  // towards that neighbour [px]
  const float pair_mean = 0.5f * ((pair_n ? ln : ls) + m);
  // walk along the edge, on the line between the two rows (columns), both ways, until the luma
  // there leaves the pair's mean by a quarter of the step: the ends of the edge
  const float fx = static_cast<float>(x), fy = static_cast<float>(y);
  const float bx = horz ? fx : fx + 0.5f * sign, by = horz ? fy + 0.5f * sign : fy;
  const float ox = horz ? 1.0f : 0.0f, oy = horz ? 0.0f : 1.0f;
  const float scaled = 0.25f * gradient;
  float dn = 0.0f, dp = 0.0f, end_n = 0.0f, end_p = 0.0f;
  bool done_n = false, done_p = false;
  for (float step : kSteps) {
    if (!done_n) {
      dn += step;
      end_n = smp.luma(L, bx - ox * dn, by - oy * dn) - pair_mean;
      done_n = std::fabs(end_n) >= scaled;
    }
    if (!done_p) {
      dp += step;
      end_p = smp.luma(L, bx + ox * dp, by + oy * dp) - pair_mean;
      done_p = std::fabs(end_p) >= scaled;
    }
    if (done_n && done_p) break;
  }
  // the nearer end decides: if the edge turns towards this pixel's side there, the pixel is
  // covered by the far side in proportion to its distance from that end (a straight edge's exact
  // coverage along a stair step)
  const bool m_below = m - pair_mean < 0.0f;
  const bool nearer_n = dn < dp;
  const float dist = std::min(dn, dp);
  const bool good = ((nearer_n ? end_n : end_p) < 0.0f) != m_below;
  const float edge_offset = good ? 0.5f - dist / (dn + dp) : 0.0f;
  const float offset = std::max(edge_offset, sub_offset);
  if (offset <= 0.0f) return;
  smp.rgb(src, horz ? fx : fx + offset * sign, horz ? fy + offset * sign : fy, out);
}

}  // namespace

void fxaa_rgb(const uint8_t* src, int w, int h, uint8_t* dst, std::vector<uint8_t>& luma) {
  if (w <= 0 || h <= 0) return;
  const size_t n = static_cast<size_t>(w) * h;
  luma.resize(n + static_cast<size_t>(w));  // + one row of edge flags
  uint8_t* L = luma.data();
  uint8_t* flag = L + n;
  for (size_t i = 0; i < n; ++i) L[i] = luma_of(src + 3 * i);
  std::memcpy(dst, src, 3 * n);
  const Sampler smp{w, h};
  for (int y = 0; y < h; ++y) {
    const uint8_t* rn = L + static_cast<size_t>(std::max(y - 1, 0)) * w;  // north row (image y grows down)
    const uint8_t* rc = L + static_cast<size_t>(y) * w;
    const uint8_t* rs = L + static_cast<size_t>(std::min(y + 1, h - 1)) * w;
    // the contrast test over the row first (branch-free, vectorised): most pixels are not edges
    for (int x = 1; x < w - 1; ++x) flag[x] = is_edge(rn, rc, rs, x - 1, x, x + 1);
    flag[0] = is_edge(rn, rc, rs, 0, 0, std::min(1, w - 1));
    flag[w - 1] = is_edge(rn, rc, rs, std::max(w - 2, 0), w - 1, w - 1);
    for (int x = 0; x < w; ++x)
      if (flag[x])
        resample(src, L, smp, rn, rc, rs, std::max(x - 1, 0), x, std::min(x + 1, w - 1), y,
                 dst + 3 * (static_cast<size_t>(y) * w + x));
  }
}

}  // namespace ps::render
