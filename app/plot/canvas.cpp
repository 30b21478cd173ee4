#include "app/plot/canvas.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace ps::plot {

Canvas::Canvas(int width, int height, Rgb bg) : w_(width), h_(height) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw std::invalid_argument("plot canvas size out of range (1..16384 px)");
  px_.resize(static_cast<size_t>(w_) * h_ * 3);
  for (size_t i = 0; i < px_.size(); i += 3) {
    px_[i] = bg.r;
    px_[i + 1] = bg.g;
    px_[i + 2] = bg.b;
  }
  reset_clip();
}

Rgb Canvas::at(int x, int y) const {
  const size_t i = (static_cast<size_t>(y) * w_ + x) * 3;
  return {px_[i], px_[i + 1], px_[i + 2]};
}

void Canvas::set_clip(int x0, int y0, int x1, int y1) {
  cx0_ = std::clamp(x0, 0, w_);
  cy0_ = std::clamp(y0, 0, h_);
  cx1_ = std::clamp(x1, 0, w_);
  cy1_ = std::clamp(y1, 0, h_);
}

void Canvas::reset_clip() { set_clip(0, 0, w_, h_); }

void Canvas::blend(int x, int y, Rgb c, double a) {
  if (x < cx0_ || y < cy0_ || x >= cx1_ || y >= cy1_ || !(a > 0)) return;
  a = std::min(a, 1.0);
  uint8_t* p = &px_[(static_cast<size_t>(y) * w_ + x) * 3];
  p[0] = static_cast<uint8_t>(std::lround(p[0] + (c.r - p[0]) * a));
  p[1] = static_cast<uint8_t>(std::lround(p[1] + (c.g - p[1]) * a));
  p[2] = static_cast<uint8_t>(std::lround(p[2] + (c.b - p[2]) * a));
}

void Canvas::fill_rect(int x0, int y0, int x1, int y1, Rgb c) {
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  for (int y = std::max(y0, cy0_); y < std::min(y1, cy1_); ++y)
    for (int x = std::max(x0, cx0_); x < std::min(x1, cx1_); ++x) blend(x, y, c, 1.0);
}

void Canvas::rect_outline(int x0, int y0, int x1, int y1, Rgb c) {
  fill_rect(x0, y0, x1, y0 + 1, c);
  fill_rect(x0, y1 - 1, x1, y1, c);
  fill_rect(x0, y0, x0 + 1, y1, c);
  fill_rect(x1 - 1, y0, x1, y1, c);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, double width) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  // Segments far outside the canvas are clipped coarsely first so a wild value costs nothing.
  const double big = 4.0 * (w_ + h_);
  x0 = std::clamp(x0, -big, big);
  x1 = std::clamp(x1, -big, big);
  y0 = std::clamp(y0, -big, big);
  y1 = std::clamp(y1, -big, big);
  const double hw = 0.5 * width;
  const int bx0 = std::max(cx0_, static_cast<int>(std::floor(std::min(x0, x1) - hw - 1)));
  const int bx1 = std::min(cx1_ - 1, static_cast<int>(std::ceil(std::max(x0, x1) + hw + 1)));
  const int by0 = std::max(cy0_, static_cast<int>(std::floor(std::min(y0, y1) - hw - 1)));
  const int by1 = std::min(cy1_ - 1, static_cast<int>(std::ceil(std::max(y0, y1) + hw + 1)));
  const double dx = x1 - x0, dy = y1 - y0;
  const double len2 = dx * dx + dy * dy;
  for (int y = by0; y <= by1; ++y) {
    for (int x = bx0; x <= bx1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      double t = len2 > 0 ? ((px - x0) * dx + (py - y0) * dy) / len2 : 0.0;
      t = std::clamp(t, 0.0, 1.0);
      const double ex = px - (x0 + t * dx), ey = py - (y0 + t * dy);
      const double d = std::sqrt(ex * ex + ey * ey);
      const double a = std::clamp(hw + 0.5 - d, 0.0, 1.0);
      if (a > 0) blend(x, y, c, a);
    }
  }
}

void Canvas::dashed_line(double x0, double y0, double x1, double y1, Rgb c, double width,
                         double dash, double gap) {
  const double len = std::hypot(x1 - x0, y1 - y0);
  if (!(len > 0) || !(dash > 0) || gap < 0) return line(x0, y0, x1, y1, c, width);
  const double ux = (x1 - x0) / len, uy = (y1 - y0) / len;
  for (double s = 0; s < len; s += dash + gap) {
    const double e = std::min(len, s + dash);
    line(x0 + ux * s, y0 + uy * s, x0 + ux * e, y0 + uy * e, c, width);
  }
}

void Canvas::fill_circle(double cx, double cy, double r, Rgb c) {
  if (!std::isfinite(cx) || !std::isfinite(cy)) return;
  const int bx0 = std::max(cx0_, static_cast<int>(std::floor(cx - r - 1)));
  const int bx1 = std::min(cx1_ - 1, static_cast<int>(std::ceil(cx + r + 1)));
  const int by0 = std::max(cy0_, static_cast<int>(std::floor(cy - r - 1)));
  const int by1 = std::min(cy1_ - 1, static_cast<int>(std::ceil(cy + r + 1)));
  for (int y = by0; y <= by1; ++y)
    for (int x = bx0; x <= bx1; ++x) {
      const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      blend(x, y, c, std::clamp(r + 0.5 - d, 0.0, 1.0));
    }
}

void Canvas::fill_polygon(const std::vector<double>& xy, Rgb c) {
  const size_t n = xy.size() / 2;
  if (n < 3) return;
  double minx = xy[0], maxx = xy[0], miny = xy[1], maxy = xy[1];
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(xy[2 * i]) || !std::isfinite(xy[2 * i + 1])) return;
    minx = std::min(minx, xy[2 * i]);
    maxx = std::max(maxx, xy[2 * i]);
    miny = std::min(miny, xy[2 * i + 1]);
    maxy = std::max(maxy, xy[2 * i + 1]);
  }
  // 4x4 supersampling of the even-odd rule gives a cheap anti-aliased edge.
  for (int y = std::max(cy0_, static_cast<int>(std::floor(miny)));
       y <= std::min(cy1_ - 1, static_cast<int>(std::ceil(maxy))); ++y)
    for (int x = std::max(cx0_, static_cast<int>(std::floor(minx)));
         x <= std::min(cx1_ - 1, static_cast<int>(std::ceil(maxx))); ++x) {
      int inside = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
          const double px = x + (sx + 0.5) / 4, py = y + (sy + 0.5) / 4;
          bool in = false;
          for (size_t i = 0, j = n - 1; i < n; j = i++) {
            const double xi = xy[2 * i], yi = xy[2 * i + 1], xj = xy[2 * j], yj = xy[2 * j + 1];
            if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi) in = !in;
          }
          inside += in;
        }
      if (inside) blend(x, y, c, inside / 16.0);
    }
}

void Canvas::marker(Marker m, double cx, double cy, double size, Rgb c) {
  const double r = 0.5 * size;
  switch (m) {
    case Marker::None:
      return;
    case Marker::Circle:
      return fill_circle(cx, cy, r, c);
    case Marker::Square:
      return fill_polygon({cx - r * 0.85, cy - r * 0.85, cx + r * 0.85, cy - r * 0.85,
                           cx + r * 0.85, cy + r * 0.85, cx - r * 0.85, cy + r * 0.85},
                          c);
    case Marker::Triangle:
      return fill_polygon({cx, cy - r, cx + r, cy + r * 0.8, cx - r, cy + r * 0.8}, c);
    case Marker::Diamond:
      return fill_polygon({cx, cy - r, cx + r, cy, cx, cy + r, cx - r, cy}, c);
    case Marker::Cross:
      line(cx - r * 0.8, cy - r * 0.8, cx + r * 0.8, cy + r * 0.8, c, std::max(1.5, size / 5));
      return line(cx - r * 0.8, cy + r * 0.8, cx + r * 0.8, cy - r * 0.8, c,
                  std::max(1.5, size / 5));
    case Marker::Plus:
      line(cx - r, cy, cx + r, cy, c, std::max(1.5, size / 5));
      return line(cx, cy - r, cx, cy + r, c, std::max(1.5, size / 5));
    case Marker::Star: {
      std::vector<double> p;
      for (int k = 0; k < 10; ++k) {
        const double a = -M_PI / 2 + k * M_PI / 5, rr = (k % 2) ? r * 0.45 : r * 1.1;
        p.push_back(cx + rr * std::cos(a));
        p.push_back(cy + rr * std::sin(a));
      }
      return fill_polygon(p, c);
    }
  }
}

namespace {
// stb_easy_font indexes its glyph table by (char - 32) without a check: anything outside
// printable ASCII (control bytes, UTF-8 such as "µ") becomes '?' before it gets there.
std::string printable(const std::string& s) {
  std::string out = s;
  for (char& ch : out)
    if (ch != '\n' && (static_cast<unsigned char>(ch) < 32 || static_cast<unsigned char>(ch) > 126)) ch = '?';
  return out;
}
struct Quad {
  float x0, y0, x1, y1;
};
// stb_easy_font emits one axis-aligned quad per stroke segment at 1 px per font unit.
std::vector<Quad> glyph_quads(const std::string& s) {
  std::string copy = printable(s);
  // A glyph is at most ~12 strokes of 64 bytes; stb silently truncates a short buffer.
  std::vector<char> buf(copy.size() * 1024 + 1024);
  const int n = stb_easy_font_print(0, 0, copy.data(), nullptr, buf.data(), static_cast<int>(buf.size()));
  std::vector<Quad> quads;
  quads.reserve(n);
  for (int q = 0; q < n; ++q) {
    const float* v0 = reinterpret_cast<const float*>(buf.data() + q * 64);
    const float* v2 = reinterpret_cast<const float*>(buf.data() + q * 64 + 32);
    quads.push_back({v0[0], v0[1], v2[0], v2[1]});
  }
  return quads;
}
}  // namespace

int Canvas::text_width(const std::string& s, int scale) {
  std::string copy = printable(s);
  return stb_easy_font_width(copy.data()) * scale;
}

int Canvas::text_height(int scale) { return 8 * scale; }

void Canvas::text(int x, int y, const std::string& s, Rgb c, int scale, bool vertical) {
  const int w = text_width(s, scale);
  for (const Quad& q : glyph_quads(s)) {
    const int qx0 = static_cast<int>(std::lround(q.x0 * scale)), qx1 = static_cast<int>(std::lround(q.x1 * scale));
    const int qy0 = static_cast<int>(std::lround(q.y0 * scale)), qy1 = static_cast<int>(std::lround(q.y1 * scale));
    if (!vertical) {
      fill_rect(x + qx0, y + qy0, x + qx1, y + qy1, c);
    } else {
      // Rotate counter-clockwise: text x runs upwards from the box bottom, text y runs right.
      fill_rect(x + qy0, y + (w - qx1), x + qy1, y + (w - qx0), c);
    }
  }
}

}  // namespace ps::plot
