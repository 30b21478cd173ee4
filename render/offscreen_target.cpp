// A multisampled offscreen framebuffer with its single-sample resolve target (offscreen_target.h).
#include "render/offscreen_target.h"

#include <algorithm>
#include <string>

#include "render/gl_api.h"
#include "render/render_error.h"

namespace ps::render {

using gl::api;

OffscreenTarget::OffscreenTarget(int w, int h, int samples) : w_(w), h_(h), samples_(samples) {
  if (!gl::loaded()) throw RenderError("offscreen target without a current OpenGL context");
  if (w < 1 || h < 1 || w > 8192 || h > 8192)
    throw RenderError("image size " + std::to_string(w) + "x" + std::to_string(h) + " outside 1..8192 per side");
  int max_samples = 0;
  api.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::clamp(samples, 0, max_samples);
  auto make = [&](unsigned& fbo, unsigned& col, unsigned& dep, int ns) {
    api.GenFramebuffers(1, &fbo);
    api.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    api.GenRenderbuffers(1, &col);
    api.BindRenderbuffer(GL_RENDERBUFFER, col);
    if (ns > 1) api.RenderbufferStorageMultisample(GL_RENDERBUFFER, ns, GL_RGBA8, w, h);
    else api.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    api.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, col);
    api.GenRenderbuffers(1, &dep);
    api.BindRenderbuffer(GL_RENDERBUFFER, dep);
    if (ns > 1) api.RenderbufferStorageMultisample(GL_RENDERBUFFER, ns, GL_DEPTH_COMPONENT24, w, h);
    else api.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    api.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, dep);
    if (api.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("offscreen framebuffer " + std::to_string(w) + "x" + std::to_string(h) + " incomplete");
  };
  make(fbo_, colour_, depth_, 0);
  if (samples_ > 1) make(fbo_ms_, colour_ms_, depth_ms_, samples_);
  scratch_.resize(4 * static_cast<size_t>(w) * h);
}

OffscreenTarget::~OffscreenTarget() {
  if (!gl::loaded()) return;
  api.BindFramebuffer(GL_FRAMEBUFFER, 0);
  for (unsigned* f : {&fbo_, &fbo_ms_})
    if (*f) api.DeleteFramebuffers(1, f);
  for (unsigned* r : {&colour_, &depth_, &colour_ms_, &depth_ms_})
    if (*r) api.DeleteRenderbuffers(1, r);
}

void OffscreenTarget::bind() {
  api.BindFramebuffer(GL_FRAMEBUFFER, samples_ > 1 ? fbo_ms_ : fbo_);
  api.Viewport(0, 0, w_, h_);
}

void OffscreenTarget::read_rgb(std::vector<uint8_t>& rgb) {
  if (samples_ > 1) {
    api.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_ms_);
    api.BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
    api.BlitFramebuffer(0, 0, w_, h_, 0, 0, w_, h_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  api.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  api.PixelStorei(GL_PACK_ALIGNMENT, 1);
  api.ReadPixels(0, 0, w_, h_, GL_RGBA, GL_UNSIGNED_BYTE, scratch_.data());
  rgb.resize(3 * static_cast<size_t>(w_) * h_);
  // GL rows are bottom-up
  for (int y = 0; y < h_; ++y) {
    const uint8_t* src = &scratch_[4 * static_cast<size_t>(h_ - 1 - y) * w_];
    uint8_t* dst = &rgb[3 * static_cast<size_t>(y) * w_];
    for (int x = 0; x < w_; ++x) {
      dst[3 * x] = src[4 * x];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 2];
    }
  }
  api.BindFramebuffer(GL_FRAMEBUFFER, samples_ > 1 ? fbo_ms_ : fbo_);
}

}  // namespace ps::render
