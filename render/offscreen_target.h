// Where headless views are drawn: an offscreen framebuffer, read back as RGB (frames, reports,
// tests). Needs a current GL context with the table of gl_api.h loaded.
#pragma once
#include <cstdint>
#include <vector>

namespace ps::render {

// A multisampled offscreen framebuffer (colour + depth) with a single-sample resolve target.
class OffscreenTarget {
 public:
  // 1..8192 per side; samples 0 or 1 = no multisampling. Throws RenderError.
  OffscreenTarget(int width, int height, int samples = 4);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;
  void bind();                                   // draw into it
  void read_rgb(std::vector<uint8_t>& rgb);      // resolve, read back, rows top-down (3 w h bytes)
  int width() const { return w_; }
  int height() const { return h_; }

 private:
  int w_, h_, samples_;
  unsigned fbo_ms_ = 0, colour_ms_ = 0, depth_ms_ = 0, fbo_ = 0, colour_ = 0, depth_ = 0;
  std::vector<uint8_t> scratch_;
};

}  // namespace ps::render
