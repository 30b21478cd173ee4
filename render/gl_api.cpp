#include "render/gl_api.h"

#include <string>

#include "render/render_error.h"

namespace ps::gl {

Api api;
static bool g_loaded = false;

void load(GetProc get) {
  Api a;
#define PS_GL_LOAD(type, name)                                                              \
  a.name = reinterpret_cast<type>(get("gl" #name));                                         \
  if (!a.name) throw ps::render::RenderError("OpenGL entry point gl" #name " not available: " \
                                             "the context is not OpenGL 3.3 core");
  PS_GL_FUNCTIONS(PS_GL_LOAD)
#undef PS_GL_LOAD
  api = a;
  g_loaded = true;
}

bool loaded() { return g_loaded; }

}  // namespace ps::gl
