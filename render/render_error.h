// Errors of the renderer and its contexts: no display / EGL / OSMesa, a shader that fails, an
// incomplete framebuffer. One clear message; the app reports it and exits non-zero.
#pragma once
#include <stdexcept>
#include <string>

namespace ps::render {

struct RenderError : std::runtime_error {
  explicit RenderError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace ps::render
