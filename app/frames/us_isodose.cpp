#include "app/frames/us_isodose.h"

#include <algorithm>
#include <cmath>

namespace ps::frames {

dosimetry::PixelPlane pixel_plane(const us::PlaneImager& im, const us::ProbeView& probe) {
  const us::PlaneFrame f = im.frame(probe);
  const double px = im.pixel_s(1.0) - im.pixel_s(0.0);  // [m]
  dosimetry::PixelPlane p;
  p.p00_mm = 1e3 * (f.origin + im.pixel_s(0.0) * f.right + im.pixel_t(0.0) * f.up);
  p.dcol_mm = 1e3 * px * f.right;
  p.drow_mm = -1e3 * px * f.up;  // rows run down the screen, away from "up"
  p.width = im.image().width > 0 ? im.image().width : im.settings().width;
  p.height = im.image().height > 0 ? im.image().height : im.settings().height;
  return p;
}

std::vector<double> isodose_levels_gy(double rx) {
  std::vector<double> v;
  for (double l : dosimetry::kIsodoseLevels) v.push_back(l * rx);
  return v;
}

void plane_isodose_lines(const dosimetry::DoseField& f, const dosimetry::PixelPlane& plane, std::vector<dosimetry::IsoSegment>& out) {
  dosimetry::plane_isodose(f, plane, isodose_levels_gy(f.prescription_gy), 2, out);
}

void draw_isodose_rgb(const std::vector<uint8_t>& gray, int w, int h, const std::vector<dosimetry::IsoSegment>& segs,
                      std::vector<uint8_t>& rgb) {
  rgb.resize(3 * gray.size());
  for (size_t i = 0; i < gray.size(); ++i) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = gray[i];
  auto plot = [&](int x, int y, const std::array<uint8_t, 3>& c) {
    if (x < 0 || y < 0 || x >= w || y >= h) return;
    uint8_t* p = &rgb[3 * (static_cast<size_t>(y) * w + x)];
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
  };
  for (const dosimetry::IsoSegment& s : segs) {
    const auto& c = kIsodoseRgb[std::min<size_t>(s.level, kIsodoseRgb.size() - 1)];
    const float dx = s.x1 - s.x0, dy = s.y1 - s.y0;
    const int n = std::max(1, static_cast<int>(std::ceil(2.0f * std::max(std::abs(dx), std::abs(dy)))));
    for (int k = 0; k <= n; ++k) {
      const float t = static_cast<float>(k) / n;
      // a 2 x 2 block around the point (pixel centres at integers): 2 px wide lines
      const float x = s.x0 + t * dx, y = s.y0 + t * dy;
      const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
      plot(x0, y0, c);
      plot(x0 + 1, y0, c);
      plot(x0, y0 + 1, c);
      plot(x0 + 1, y0 + 1, c);
    }
  }
}

}  // namespace ps::frames
