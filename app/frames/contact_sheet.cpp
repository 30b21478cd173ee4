#include "app/frames/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/io/png_write.h"
#include "app/plot/chart.h"

namespace ps::frames {

Thumb make_thumb(const std::vector<uint8_t>& rgb, int w, int h, int width, double time) {
  Thumb t;
  t.time = time;
  t.w = std::min(width, w);
  t.h = std::max(1, static_cast<int>(std::lround(static_cast<double>(h) * t.w / w)));
  t.rgb.assign(3 * static_cast<size_t>(t.w) * t.h, 0);
  for (int y = 0; y < t.h; ++y)
    for (int x = 0; x < t.w; ++x) {
      const int x0 = x * w / t.w, x1 = std::max(x0 + 1, (x + 1) * w / t.w);
      const int y0 = y * h / t.h, y1 = std::max(y0 + 1, (y + 1) * h / t.h);
      for (int c = 0; c < 3; ++c) {
        unsigned sum = 0;
        for (int yy = y0; yy < y1; ++yy)
          for (int xx = x0; xx < x1; ++xx) sum += rgb[3 * (static_cast<size_t>(yy) * w + xx) + c];
        t.rgb[3 * (static_cast<size_t>(y) * t.w + x) + c] = static_cast<uint8_t>(sum / ((x1 - x0) * (y1 - y0)));
      }
    }
  return t;
}

void write_contact_sheet(const std::string& path, const ContactSheetInput& in) {
  const int tw = in.thumbs.empty() ? 640 : in.thumbs[0].w, th = in.thumbs.empty() ? 360 : in.thumbs[0].h;
  const int pad = 8, label = 22;
  const int W = 2 * tw + 3 * pad;
  const bool needle = !in.depth_mm.empty(), timed = !needle && !in.over_time.t_s.empty();
  const int plot_h = needle || timed ? 480 : 0;
  const int rows = in.thumbs.empty() ? 0 : (static_cast<int>(in.thumbs.size()) + 1) / 2;
  const int H = rows * (th + label + pad) + pad + (plot_h > 0 ? plot_h + pad : 0);
  plot::Canvas sheet(W, H, {24, 26, 30});
  for (size_t k = 0; k < in.thumbs.size(); ++k) {
    const Thumb& t = in.thumbs[k];
    const int ox = pad + static_cast<int>(k % 2) * (tw + pad), oy = pad + static_cast<int>(k / 2) * (th + label + pad);
    char cap[64];
    std::snprintf(cap, sizeof cap, "t = %.3f s", t.time);
    sheet.text(ox, oy + 2, cap, {230, 230, 230}, 2);
    for (int y = 0; y < t.h; ++y)
      for (int x = 0; x < t.w; ++x) {
        const uint8_t* p = &t.rgb[3 * (static_cast<size_t>(y) * t.w + x)];
        sheet.fill_rect(ox + x, oy + label + y, ox + x + 1, oy + label + y + 1, {p[0], p[1], p[2]});
      }
  }
  if (plot_h == 0) {  // no instrument readout to plot
    ps::write_png_atomic(path, sheet.width(), sheet.height(), 3, sheet.pixels().data());
    return;
  }
  plot::Chart ch;
  plot::Series s;
  s.color = plot::palette(0);
  if (timed) {
    ch.title = in.title + ": " + in.over_time.what + " versus time";
    ch.x.label = "time [s]";
    ch.y.label = in.over_time.y_label;
    s.label = in.over_time.what;
    s.x = in.over_time.t_s;
    s.y = in.over_time.y;
  } else {
    ch.title = in.title + ": needle force versus insertion depth";
    ch.x.label = "insertion depth [mm]";
    ch.y.label = "axial force on the needle [N]";
    // the curve is each tick's mean; an event marker is the peak force up to that event, which
    // during a gun stroke (~1 mm per tick) stands well above the tick's mean
    s.label = "force (tick mean)";
    s.x = in.depth_mm;
    s.y = in.force_n;
  }
  ch.series.push_back(s);
  if (!in.marks.empty()) {
    plot::Series m;
    m.label = "puncture / bone / core (peak force)";
    m.line = false;
    m.marker = plot::Marker::Circle;
    m.color = plot::palette(3);
    for (const auto& [d, f] : in.marks) {
      m.x.push_back(d);
      m.y.push_back(f);
    }
    ch.series.push_back(m);
  }
  ch.legend = plot::LegendPos::TopLeft;
  const plot::Canvas pc = plot::render(ch, W - 2 * pad, plot_h);
  const int oy = H - plot_h - pad;
  for (int y = 0; y < pc.height(); ++y)
    for (int x = 0; x < pc.width(); ++x) sheet.fill_rect(pad + x, oy + y, pad + x + 1, oy + y + 1, pc.at(x, y));
  ps::write_png_atomic(path, sheet.width(), sheet.height(), 3, sheet.pixels().data());
}

}  // namespace ps::frames
