#include "app/plot/chart.h"

#include <algorithm>
#include <cstdio>
#include <limits>

namespace ps::plot {

Rgb palette(int i) {
  static const Rgb k[] = {{31, 119, 180}, {214, 39, 40},  {44, 160, 44},  {255, 127, 14},
                          {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {80, 80, 80},
                          {188, 189, 34},  {23, 190, 207}};
  return k[((i % 10) + 10) % 10];
}

std::vector<double> linear_ticks(double lo, double hi, int target) {
  std::vector<double> t;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo) || target < 2) return t;
  const double raw = (hi - lo) / (target - 1);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double step = (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * mag;
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (int k = 0; k < 1000; ++k) {
    const double v = first + k * step;
    if (v > hi + step * 1e-9) break;
    t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  return t;
}

std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> t;
  if (!(lo > 0) || !(hi > lo) || !std::isfinite(hi)) return t;
  const int d0 = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
  const int d1 = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
  const int decades = d1 - d0;
  const int every = std::max(1, decades / 8);  // at most ~8 labelled decades
  for (int d = d0; d <= d1; ++d) {
    for (double m : {1.0, 2.0, 5.0}) {
      if (m != 1.0 && decades >= 4) continue;
      if (m == 1.0 && (d - d0) % every) continue;
      const double v = m * std::pow(10.0, d);
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t.push_back(v);
    }
  }
  return t;
}

std::string tick_label(double v, double step, bool log) {
  char buf[32];
  if (v == 0) return "0";
  const double a = std::abs(v);
  if (log || a >= 1e5 || a < 1e-3) {
    if (a >= 1e-3 && a < 1e5) {
      std::snprintf(buf, sizeof buf, "%g", v);
    } else {
      // 1e-05 -> 1e-5, 2e+06 -> 2e6: shorter under a tick.
      const int e = static_cast<int>(std::floor(std::log10(a) + 1e-9));
      const double m = v / std::pow(10.0, e);
      if (std::abs(m - std::round(m)) < 1e-6)
        std::snprintf(buf, sizeof buf, "%de%d", static_cast<int>(std::round(m)), e);
      else
        std::snprintf(buf, sizeof buf, "%.2ge%d", m, e);
    }
    return buf;
  }
  const int decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step) + 1e-9)), 0, 6);
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

namespace {

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
};

bool usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

// The axis extent: the user's min/max where given, else the data padded to tick boundaries.
Range axis_range(const Chart& c, bool is_x) {
  const Axis& ax = is_x ? c.x : c.y;
  Range r;
  for (const Series& s : c.series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      const double v = is_x ? s.x[i] : s.y[i];
      const double other = is_x ? s.y[i] : s.x[i];
      if (!usable(v, ax.log) || !usable(other, is_x ? c.y.log : c.x.log)) continue;
      r.lo = std::min(r.lo, v);
      r.hi = std::max(r.hi, v);
    }
  if (!(r.lo <= r.hi)) r = ax.log ? Range{1, 10} : Range{0, 1};
  if (ax.log) {
    if (r.hi <= r.lo * 1.0001) { r.lo /= 2; r.hi *= 2; }
    // Pad to the next 1-2-5 value so the data never sits on the frame.
    auto down = [](double v) {
      const double d = std::pow(10.0, std::floor(std::log10(v)));
      for (double m : {5.0, 2.0, 1.0}) if (m * d <= v) return m * d;
      return d;
    };
    auto up = [](double v) {
      const double d = std::pow(10.0, std::floor(std::log10(v)));
      for (double m : {1.0, 2.0, 5.0, 10.0}) if (m * d >= v * (1 - 1e-12)) return m * d;
      return 10 * d;
    };
    r.lo = down(r.lo * 0.999);
    r.hi = up(r.hi * 1.001);
  } else {
    if (r.hi - r.lo < 1e-12 * std::max(1.0, std::abs(r.hi))) {
      const double pad = std::max(std::abs(r.hi) * 0.1, 1e-9);
      r.lo -= pad;
      r.hi += pad;
    }
    const double pad = 0.04 * (r.hi - r.lo);
    r.lo -= pad;
    r.hi += pad;
  }
  if (std::isfinite(ax.min) && usable(ax.min, ax.log)) r.lo = ax.min;
  if (std::isfinite(ax.max) && usable(ax.max, ax.log)) r.hi = ax.max;
  if (!(r.hi > r.lo)) r.hi = ax.log ? r.lo * 10 : r.lo + 1;
  return r;
}

}  // namespace

Canvas render(const Chart& chart, int width, int height) {
  Canvas cv(width, height);
  const int ts = std::max(1, std::min(width, height) / 320);  // text scale
  const int th = Canvas::text_height(ts);
  const Rgb ink{20, 20, 20}, grid{225, 225, 225}, frame{60, 60, 60};

  const Range xr = axis_range(chart, true), yr = axis_range(chart, false);
  const std::vector<double> xt = chart.x.log ? log_ticks(xr.lo, xr.hi) : linear_ticks(xr.lo, xr.hi);
  const std::vector<double> yt = chart.y.log ? log_ticks(yr.lo, yr.hi) : linear_ticks(yr.lo, yr.hi);
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1, ystep = yt.size() > 1 ? yt[1] - yt[0] : 1;
  int ylab_w = 0;
  for (double v : yt) ylab_w = std::max(ylab_w, Canvas::text_width(tick_label(v, ystep, chart.y.log), ts));

  const int pad = 6 * ts;
  const int left = pad + (chart.y.label.empty() ? 0 : th + pad) + ylab_w + pad + 4 * ts;
  const int right = width - 8 * ts - Canvas::text_width(xt.empty() ? "" : tick_label(xt.back(), xstep, chart.x.log), ts) / 2;
  const int top = pad + (chart.title.empty() ? 0 : th * 3 / 2 + 2 * pad);
  const int bottom = height - pad - (chart.x.label.empty() ? 0 : th + pad) - th - pad - 6 * ts;
  if (right - left < 20 || bottom - top < 20) return cv;  // too small to draw a plot area

  auto map = [](double v, const Range& r, bool log, double a, double b) {
    const double t = log ? (std::log10(v) - std::log10(r.lo)) / (std::log10(r.hi) - std::log10(r.lo))
                         : (v - r.lo) / (r.hi - r.lo);
    return a + t * (b - a);
  };
  auto px = [&](double v) { return map(v, xr, chart.x.log, left, right); };
  auto py = [&](double v) { return map(v, yr, chart.y.log, bottom, top); };

  // Title, axis labels.
  if (!chart.title.empty()) {
    const int tw = Canvas::text_width(chart.title, ts + 1);
    cv.text(std::max(pad, (left + right - tw) / 2), pad, chart.title, ink, ts + 1);
  }
  if (!chart.x.label.empty()) {
    const int lw = Canvas::text_width(chart.x.label, ts);
    cv.text((left + right - lw) / 2, height - pad - th, chart.x.label, ink, ts);
  }
  if (!chart.y.label.empty()) {
    const int lw = Canvas::text_width(chart.y.label, ts);
    cv.text(pad, std::max(0, (top + bottom - lw) / 2), chart.y.label, ink, ts, true);
  }

  // Grid, minor log ticks, ticks and their labels.
  const int tick = 5 * ts;
  if (chart.x.log) {
    for (int d = static_cast<int>(std::floor(std::log10(xr.lo))); d <= std::ceil(std::log10(xr.hi)); ++d)
      for (int m = 1; m <= 9; ++m) {
        const double v = m * std::pow(10.0, d);
        if (v < xr.lo || v > xr.hi) continue;
        const double x = px(v);
        cv.line(x, bottom, x, bottom - tick / 2, frame, 1);
      }
  }
  if (chart.y.log) {
    for (int d = static_cast<int>(std::floor(std::log10(yr.lo))); d <= std::ceil(std::log10(yr.hi)); ++d)
      for (int m = 1; m <= 9; ++m) {
        const double v = m * std::pow(10.0, d);
        if (v < yr.lo || v > yr.hi) continue;
        const double y = py(v);
        cv.line(left, y, left + tick / 2, y, frame, 1);
      }
  }
  for (double v : xt) {
    const double x = std::round(px(v)) + 0.5;
    if (chart.grid) cv.line(x, top, x, bottom, grid, 1);
    cv.line(x, bottom, x, bottom - tick, frame, 1.2);
    const std::string s = tick_label(v, xstep, chart.x.log);
    cv.text(static_cast<int>(x) - Canvas::text_width(s, ts) / 2, bottom + 5 * ts, s, ink, ts);
  }
  for (double v : yt) {
    const double y = std::round(py(v)) + 0.5;
    if (chart.grid) cv.line(left, y, right, y, grid, 1);
    cv.line(left, y, left + tick, y, frame, 1.2);
    const std::string s = tick_label(v, ystep, chart.y.log);
    cv.text(left - 3 * ts - Canvas::text_width(s, ts), static_cast<int>(y) - th / 2 + ts, s, ink, ts);
  }

  // Series, clipped to the plot area.
  cv.set_clip(left + 1, top + 1, right, bottom);
  for (const Series& s : chart.series) {
    const size_t n = std::min(s.x.size(), s.y.size());
    auto ok = [&](size_t i) { return usable(s.x[i], chart.x.log) && usable(s.y[i], chart.y.log); };
    if (s.line) {
      bool have = false;
      double lx = 0, ly = 0;
      for (size_t i = 0; i < n; ++i) {
        if (!ok(i)) { have = false; continue; }
        const double x = px(s.x[i]), y = py(s.y[i]);
        if (have) {
          if (s.dashed) cv.dashed_line(lx, ly, x, y, s.color, s.line_width, 8 * ts, 5 * ts);
          else cv.line(lx, ly, x, y, s.color, s.line_width);
        }
        lx = x;
        ly = y;
        have = true;
      }
    }
    if (s.marker != Marker::None)
      for (size_t i = 0; i < n; ++i)
        if (ok(i)) cv.marker(s.marker, px(s.x[i]), py(s.y[i]), s.marker_size, s.color);
  }
  cv.reset_clip();
  cv.rect_outline(left, top, right + 1, bottom + 1, frame);

  // Legend: a white box with a sample of each series' line and marker.
  std::vector<const Series*> listed;
  for (const Series& s : chart.series) if (!s.label.empty()) listed.push_back(&s);
  if (chart.legend != LegendPos::None && !listed.empty()) {
    const int sample = 26 * ts, row = th + 4 * ts;
    int lw = 0;
    for (const Series* s : listed) lw = std::max(lw, Canvas::text_width(s->label, ts));
    const int bw = sample + 3 * pad / 2 + lw + pad, bh = static_cast<int>(listed.size()) * row + pad;
    auto box = [&](LegendPos pos, int& bx, int& by) {
      const bool l = pos == LegendPos::TopLeft || pos == LegendPos::BottomLeft;
      const bool t = pos == LegendPos::TopLeft || pos == LegendPos::TopRight;
      bx = l ? left + pad : right - pad - bw;
      by = t ? top + pad : bottom - pad - bh;
    };
    LegendPos pos = chart.legend;
    if (pos == LegendPos::Best) {
      // how much of the data each corner's box would hide: markers, and points every few pixels
      // along the lines (a marker's half size around the box counts as under it)
      int fewest = -1;
      for (LegendPos c : {LegendPos::TopRight, LegendPos::TopLeft, LegendPos::BottomRight, LegendPos::BottomLeft}) {
        int bx = 0, by = 0;
        box(c, bx, by);
        int hidden = 0;
        for (const Series& s : chart.series) {
          const double m = s.marker == Marker::None ? s.line_width : s.marker_size / 2;
          auto under = [&](double x, double y) { return x >= bx - m && x <= bx + bw + m && y >= by - m && y <= by + bh + m; };
          const size_t n = std::min(s.x.size(), s.y.size());
          bool have = false;
          double lx = 0, ly = 0;
          for (size_t i = 0; i < n; ++i) {
            if (!(usable(s.x[i], chart.x.log) && usable(s.y[i], chart.y.log))) { have = false; continue; }
            const double x = px(s.x[i]), y = py(s.y[i]);
            hidden += under(x, y) ? 10 : 0;  // a marker or a vertex weighs more than a stretch of line
            if (s.line && have) {
              const int steps = std::max(1, static_cast<int>(std::hypot(x - lx, y - ly) / (4.0 * ts)));
              for (int k = 1; k < steps; ++k) hidden += under(lx + (x - lx) * k / steps, ly + (y - ly) * k / steps);
            }
            lx = x;
            ly = y;
            have = true;
          }
        }
        if (fewest < 0 || hidden < fewest) {
          fewest = hidden;
          pos = c;
        }
      }
    }
    int bx = 0, by = 0;
    box(pos, bx, by);
    cv.fill_rect(bx, by, bx + bw, by + bh, {255, 255, 255});
    cv.rect_outline(bx, by, bx + bw, by + bh, {160, 160, 160});
    for (size_t k = 0; k < listed.size(); ++k) {
      const Series& s = *listed[k];
      const int cy = by + pad / 2 + static_cast<int>(k) * row + row / 2;
      const int sx = bx + pad / 2;
      if (s.line) {
        if (s.dashed) cv.dashed_line(sx, cy, sx + sample, cy, s.color, s.line_width, 6 * ts, 4 * ts);
        else cv.line(sx, cy, sx + sample, cy, s.color, s.line_width);
      }
      if (s.marker != Marker::None) cv.marker(s.marker, sx + sample / 2.0, cy, s.marker_size, s.color);
      cv.text(sx + sample + pad, cy - th / 2 + ts, s.label, ink, ts);
    }
  }
  return cv;
}

}  // namespace ps::plot
