// The renderer's 2D overlay and heads-up display: text (stb_easy_font quads), rectangles, and the
// HUD drawn over each view (title, time, instrument read-outs, legend, displacement colour bar).
#include <algorithm>
#include <cstdio>
#include <string>

#include "engine/tools/tool_kind.h"
#include "render/primitive_batches.h"
#include "render/renderer.h"

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace ps::render {

void Renderer::text(float x, float y, const std::string& s, Rgba c, float scale) {
  Gpu& g = *gpu_;
  std::vector<char>& buf = g.text_scratch;
  unsigned char col[4] = {to_byte(c.r), to_byte(c.g), to_byte(c.b), to_byte(c.a)};
  std::string copy = s;
  const int quads = stb_easy_font_print(0, 0, copy.data(), col, buf.data(), static_cast<int>(buf.size()));
  struct Q { float x, y, z; unsigned char c[4]; };
  const Q* q = reinterpret_cast<const Q*>(buf.data());
  for (int i = 0; i < quads; ++i) {
    const Q* v = q + 4 * i;
    const int order[6] = {0, 1, 2, 0, 2, 3};
    for (int k : order)
      g.overlay.push_back({{x + scale * v[k].x, y + scale * v[k].y}, {v[k].c[0], v[k].c[1], v[k].c[2], v[k].c[3]}});
  }
}

float Renderer::text_width(const std::string& s, float scale) {
  std::string copy = s;
  return scale * static_cast<float>(stb_easy_font_width(copy.data()));
}

void Renderer::rect(float x, float y, float w, float h, Rgba c) {
  const uint8_t col[4] = {to_byte(c.r), to_byte(c.g), to_byte(c.b), to_byte(c.a)};
  const float px[6] = {x, x + w, x + w, x, x + w, x};
  const float py[6] = {y, y, y + h, y, y + h, y + h};
  for (int k = 0; k < 6; ++k) gpu_->overlay.push_back({{px[k], py[k]}, {col[0], col[1], col[2], col[3]}});
}

void Renderer::draw_hud(int width, int height, const RenderOptions& opt) {
  const Rgba white{0.95f, 0.95f, 0.95f, 1.0f}, grey{0.75f, 0.78f, 0.82f, 1.0f};
  const float s = height >= 600 ? 2.0f : 1.0f;  // text scale: 14 px tall at 720p
  float y = 8 * s;
  char line[256];
  std::snprintf(line, sizeof line, "%s   t = %.3f s", opt.title.empty() ? scene_.name.c_str() : opt.title.c_str(), last_time_);
  rect(0, 0, static_cast<float>(width), 16 * s, {0, 0, 0, 0.45f});
  text(6 * s, 4 * s, line, white, s);
  y = 22 * s;
  {
    for (const ToolReadout& t : tools_) {
      if ((t.carries & kCarriesInsertion) && t.active) {
        const ToolKind* k = readout_kind(t);
        std::snprintf(line, sizeof line, "%s %s: depth %.1f mm, force %.2f N", k ? k->label : "instrument", t.name.data(), t.depth * 1e3, t.force);
        text(6 * s, y, line, white, s);
        y += 10 * s;
      }
    }
  }
  // legend: organ colours
  float ly = static_cast<float>(height) - 10 * s;
  for (int i = static_cast<int>(scene_.surfaces.size()) - 1; i >= -static_cast<int>(scene_.tubes.size() + scene_.markers.size()); --i) {
    Rgba c;
    std::string name;
    if (i >= 0) {
      if (i < static_cast<int>(opt.hidden.size()) && opt.hidden[i]) continue;
      c = scene_.surfaces[i].colour;
      name = scene_.surfaces[i].name;
    } else {
      const int j = -i - 1;
      if (j < static_cast<int>(scene_.tubes.size())) { c = scene_.tubes[j].colour; name = scene_.tubes[j].name; }
      else { c = scene_.markers[j - scene_.tubes.size()].colour; name = scene_.markers[j - scene_.tubes.size()].name; }
    }
    c.a = 1.0f;
    rect(6 * s, ly - 7 * s, 7 * s, 7 * s, c);
    text(16 * s, ly - 7 * s, name, grey, s);
    ly -= 10 * s;
  }
  if (opt.displacement) {
    // colour bar at the right edge, labelled in mm
    const float bw = 12 * s, bh = std::min(200 * s, height * 0.5f), bx = width - bw - 50 * s, by = 30 * s;
    const int steps = 32;
    for (int k = 0; k < steps; ++k) {
      const double t = 1.0 - (k + 0.5) / steps;
      rect(bx, by + bh * k / steps, bw, bh / steps + 0.5f, colour_map(t));
    }
    for (int k = 0; k <= 4; ++k) {
      std::snprintf(line, sizeof line, "%.1f", opt.displacement_max_mm * (1.0 - k / 4.0));
      text(bx + bw + 4 * s, by + bh * k / 4.0f - 3 * s, line, white, s);
    }
    text(bx - 6 * s, by - 12 * s, "|u| [mm]", white, s);
  }
}

}  // namespace ps::render
