// An RGB raster that charts draw into: anti-aliased thick lines, filled shapes, markers and
// bitmap text (stb_easy_font). No file I/O here; the caller writes the pixels with
// ps::write_png_atomic (engine/io/png_write.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace ps::plot {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};

enum class Marker { None, Circle, Square, Triangle, Diamond, Cross, Plus, Star };

class Canvas {
 public:
  Canvas(int width, int height, Rgb background = {255, 255, 255});

  int width() const { return w_; }
  int height() const { return h_; }
  // width*height*3 bytes, rows top-down: what write_png_atomic(path, w, h, 3, data) takes.
  const std::vector<uint8_t>& pixels() const { return px_; }
  Rgb at(int x, int y) const;

  // Drawing is clipped to this rectangle (pixel coordinates, inclusive-exclusive).
  void set_clip(int x0, int y0, int x1, int y1);
  void reset_clip();

  // Blends `c` into pixel (x, y) with coverage alpha in [0, 1].
  void blend(int x, int y, Rgb c, double alpha);
  void fill_rect(int x0, int y0, int x1, int y1, Rgb c);
  void rect_outline(int x0, int y0, int x1, int y1, Rgb c);
  // Anti-aliased segment of the given width [px], with round caps.
  void line(double x0, double y0, double x1, double y1, Rgb c, double width = 1.0);
  // Dashed variant: dash and gap lengths [px].
  void dashed_line(double x0, double y0, double x1, double y1, Rgb c, double width, double dash,
                   double gap);
  void fill_circle(double cx, double cy, double r, Rgb c);
  void fill_polygon(const std::vector<double>& xy, Rgb c);  // x0,y0,x1,y1,... convex or not
  // Marker of the given size (diameter) [px] centred at (cx, cy).
  void marker(Marker m, double cx, double cy, double size, Rgb c);

  // Bitmap text; `scale` multiplies the 1-pixel font (about 7 px tall, so 2 gives ~14 px).
  // (x, y) is the top-left corner. vertical=true rotates 90 degrees counter-clockwise
  // (reads bottom to top, for a y-axis label); then (x, y) is the top-left of the rotated box.
  void text(int x, int y, const std::string& s, Rgb c, int scale = 2, bool vertical = false);
  static int text_width(const std::string& s, int scale = 2);
  static int text_height(int scale = 2);

 private:
  int w_, h_;
  std::vector<uint8_t> px_;
  int cx0_, cy0_, cx1_, cy1_;
};

}  // namespace ps::plot
