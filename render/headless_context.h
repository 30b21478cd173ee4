// An OpenGL 3.3 core context with no window and no display (headless replay, tests, benchmarks):
// EGL on Mesa's surfaceless platform first, OSMesa as the fallback (toolchain.md). Both are
// opened with dlopen so that no executable links two GL providers; the renderer draws into its
// own framebuffer object, so neither needs a surface.
// PROSTATESIM_GL=egl|osmesa forces one; PROSTATESIM_EGL_LIB / PROSTATESIM_OSMESA_LIB name the
// libraries (defaults libEGL.so.1, libOSMesa.so.8).
#pragma once
#include <memory>
#include <string>

namespace ps::render {

class HeadlessContext {
 public:
  // Creates the context, makes it current on this thread and loads the GL table (gl_api.h).
  // Throws RenderError with one message saying what was tried when neither works.
  HeadlessContext();
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;

  const std::string& backend() const { return backend_; }      // "egl" or "osmesa"
  const std::string& renderer() const { return renderer_; }    // GL_RENDERER, e.g. llvmpipe
  void make_current();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::string backend_, renderer_;
};

}  // namespace ps::render
