// The CPU antialiasing pass of headless frames (render/post_antialias.h), against the exact area
// coverage of shapes whose edges are known analytically: a point-sampled (aliased) edge is
// what a rasteriser draws with one sample per pixel; the pass must bring it closer to the
// pixel's true coverage, leave flat regions and axis-aligned edges alone, and not wipe out thin
// lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "render/post_antialias.h"

namespace ps::render {
namespace {

using Inside = std::function<bool(double x, double y)>;  // pixel centres at integers

struct Pair {
  std::vector<uint8_t> aliased;   // point-sampled at pixel centres
  std::vector<double> coverage;   // exact area fraction (32 x 32 sub-samples per pixel)
};

Pair draw(int w, int h, const Inside& in) {
  Pair p;
  p.aliased.assign(3 * static_cast<size_t>(w) * h, 0);
  p.coverage.assign(static_cast<size_t>(w) * h, 0.0);
  constexpr int kSub = 32;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      if (in(x, y)) p.aliased[3 * i] = p.aliased[3 * i + 1] = p.aliased[3 * i + 2] = 255;
      int hit = 0;
      for (int sy = 0; sy < kSub; ++sy)
        for (int sx = 0; sx < kSub; ++sx) hit += in(x - 0.5 + (sx + 0.5) / kSub, y - 0.5 + (sy + 0.5) / kSub);
      p.coverage[i] = static_cast<double>(hit) / (kSub * kSub);
    }
  return p;
}

// RMS over the pixels the edge crosses (0 < coverage < 1) of |image - 255 coverage|, in grey levels
double edge_rms(const std::vector<uint8_t>& rgb, const std::vector<double>& cov) {
  double s = 0.0;
  int n = 0;
  for (size_t i = 0; i < cov.size(); ++i)
    if (cov[i] > 0.0 && cov[i] < 1.0)
      for (int k = 0; k < 3; ++k) {
        const double e = rgb[3 * i + k] - 255.0 * cov[i];
        s += e * e;
        ++n;
      }
  return n ? std::sqrt(s / n) : 0.0;
}

std::vector<uint8_t> fxaa(const std::vector<uint8_t>& src, int w, int h) {
  std::vector<uint8_t> dst(src.size());
  std::vector<uint8_t> luma;
  fxaa_rgb(src.data(), w, h, dst.data(), luma);
  return dst;
}

int max_diff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  int d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(int(a[i]) - int(b[i])));
  return d;
}

TEST(PostAntialias, FlatImageAndAxisAlignedEdgeUnchanged) {
  const int w = 40, h = 30;
  std::vector<uint8_t> flat(3 * w * h);
  for (size_t i = 0; i < flat.size(); ++i) flat[i] = static_cast<uint8_t>(40 + (i % 3) * 50);
  EXPECT_EQ(fxaa(flat, w, h), flat);
  // a vertical and a horizontal edge are not aliased: no blend along them; only the sub-pixel
  // term (kSubpix) softens the two pixels at the step, by 4 grey levels at most
  const Pair v = draw(w, h, [](double x, double) { return x < 17.0; });
  EXPECT_LE(max_diff(fxaa(v.aliased, w, h), v.aliased), 4);
  const Pair hz = draw(w, h, [](double, double y) { return y < 11.0; });
  EXPECT_LE(max_diff(fxaa(hz.aliased, w, h), hz.aliased), 4);
}

TEST(PostAntialias, SlantedEdgesMoveTowardsTheirAreaCoverage) {
  const int w = 96, h = 64;
  // half-planes at several slopes, both orientations: every one at least a quarter closer to its
  // coverage, and on average about half (about what FXAA 3 is known for; 4x multisampling does
  // better, at twice the frame's CPU on a software rasteriser)
  double ratio_sum = 0.0;
  int cases = 0;
  for (double slope : {0.2, 0.45, 0.8, 1.6, 3.5, -0.3, -2.2}) {
    const Pair p = draw(w, h, [&](double x, double y) { return y - 32.0 < slope * (x - 48.0); });
    const double before = edge_rms(p.aliased, p.coverage);
    const double after = edge_rms(fxaa(p.aliased, w, h), p.coverage);
    EXPECT_LT(after, 0.75 * before) << "slope " << slope << ": RMS " << before << " -> " << after << " grey levels";
    ratio_sum += after / before;
    ++cases;
  }
  EXPECT_LT(ratio_sum / cases, 0.55);
  // a disc: every edge orientation
  const Pair d = draw(w, h, [](double x, double y) { return std::hypot(x - 47.3, y - 31.6) < 22.0; });
  const double before = edge_rms(d.aliased, d.coverage);
  const double after = edge_rms(fxaa(d.aliased, w, h), d.coverage);
  EXPECT_LT(after, 0.6 * before) << "disc: RMS " << before << " -> " << after << " grey levels";
}

TEST(PostAntialias, ThinLineKeepsItsIntensity) {
  // a 1 px wide line at a shallow slope (the dashed needle path, a wire): blending may spread
  // it, not erase it
  const int w = 96, h = 48;
  const Pair p = draw(w, h, [](double x, double y) { return std::fabs(y - 20.0 - 0.17 * x) < 0.5; });
  const std::vector<uint8_t> out = fxaa(p.aliased, w, h);
  double in_sum = 0.0, out_sum = 0.0;
  for (size_t i = 0; i < out.size(); ++i) {
    in_sum += p.aliased[i];
    out_sum += out[i];
  }
  EXPECT_GT(out_sum / in_sum, 0.7);
  EXPECT_LT(out_sum / in_sum, 1.1);
  for (int x = 2; x < w - 2; ++x) {  // every column that shows the line still shows it, at half or more
    int peak_in = 0, peak = 0;
    for (int y = 0; y < h; ++y) {
      peak_in = std::max<int>(peak_in, p.aliased[3 * (static_cast<size_t>(y) * w + x)]);
      peak = std::max<int>(peak, out[3 * (static_cast<size_t>(y) * w + x)]);
    }
    if (peak_in == 255) EXPECT_GE(peak, 128) << "column " << x;
  }
}

TEST(PostAntialias, ImageBordersAndTinyImages) {
  // edges running into the border and 1 x 1 / 1 x N images (sanitizer builds check the reads)
  const Pair p = draw(7, 5, [](double x, double y) { return y < 0.7 * x - 1.0; });
  EXPECT_EQ(fxaa(p.aliased, 7, 5).size(), p.aliased.size());
  std::vector<uint8_t> one{10, 200, 30};
  EXPECT_EQ(fxaa(one, 1, 1), one);
  const Pair col = draw(1, 9, [](double, double y) { return y < 4.0; });
  EXPECT_LE(max_diff(fxaa(col.aliased, 1, 9), col.aliased), 4);
}

TEST(PostAntialias, ChoosesByRenderer) {
  EXPECT_EQ(resolve_antialias(Antialias::Auto, "llvmpipe (LLVM 15.0.6, 256 bits)"), Antialias::Fxaa);
  EXPECT_EQ(resolve_antialias(Antialias::Auto, "NVIDIA H200/PCIe/SSE2"), Antialias::Msaa);
  EXPECT_EQ(resolve_antialias(Antialias::None, "llvmpipe"), Antialias::None);
  Antialias a{};
  EXPECT_TRUE(parse_antialias("fxaa", a));
  EXPECT_EQ(a, Antialias::Fxaa);
  EXPECT_FALSE(parse_antialias("smaa", a));
}

}  // namespace
}  // namespace ps::render
