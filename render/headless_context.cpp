#include "render/headless_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "render/gl_api.h"
#include "render/render_error.h"

namespace ps::render {

namespace {

// OSMesa's few entry points, declared here so no OSMesa header or library is needed at build time.
using OSMesaContext = void*;
constexpr int kOsmesaFormatRgba = 0x1908;      // GL_RGBA
constexpr int kOsmesaDepthBits = 0x30, kOsmesaStencilBits = 0x31, kOsmesaAccumBits = 0x32;
constexpr int kOsmesaProfile = 0x33, kOsmesaCoreProfile = 0x34;
constexpr int kOsmesaMajor = 0x36, kOsmesaMinor = 0x37, kOsmesaFormat = 0x22;
using PfnOsmesaCreate = OSMesaContext (*)(const int*, OSMesaContext);
using PfnOsmesaMakeCurrent = unsigned char (*)(OSMesaContext, void*, unsigned, int, int);
using PfnOsmesaDestroy = void (*)(OSMesaContext);
using PfnOsmesaGetProc = void* (*)(const char*);

const char* env_or(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

// get-proc trampolines for gl::load (plain function pointers, so the library handle is global)
PFNEGLGETPROCADDRESSPROC g_egl_get = nullptr;
PfnOsmesaGetProc g_osmesa_get = nullptr;
void* egl_get(const char* n) { return reinterpret_cast<void*>(g_egl_get(n)); }
void* osmesa_get(const char* n) { return g_osmesa_get(n); }

}  // namespace

struct HeadlessContext::Impl {
  void* lib = nullptr;
  // EGL
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  PFNEGLMAKECURRENTPROC egl_make_current = nullptr;
  PFNEGLDESTROYCONTEXTPROC egl_destroy = nullptr;
  PFNEGLTERMINATEPROC egl_terminate = nullptr;
  // OSMesa
  OSMesaContext osmesa = nullptr;
  PfnOsmesaMakeCurrent osmesa_make_current = nullptr;
  PfnOsmesaDestroy osmesa_destroy = nullptr;
  std::vector<unsigned char> osmesa_buffer = std::vector<unsigned char>(4 * 4 * 4);

  ~Impl() {
    if (context != EGL_NO_CONTEXT) {
      egl_make_current(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      egl_destroy(display, context);
    }
    if (display != EGL_NO_DISPLAY && egl_terminate) egl_terminate(display);
    if (osmesa) osmesa_destroy(osmesa);
    // the library stays loaded: Mesa keeps threads and atexit handlers inside it
  }

  // empty string on success, else why not
  std::string try_egl() {
    const char* name = env_or("PROSTATESIM_EGL_LIB", "libEGL.so.1");
    lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (!lib) return std::string("EGL: cannot load ") + name;
    g_egl_get = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(lib, "eglGetProcAddress"));
    if (!g_egl_get) return "EGL: eglGetProcAddress missing";
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(g_egl_get("eglGetPlatformDisplayEXT"));
    auto initialize = reinterpret_cast<PFNEGLINITIALIZEPROC>(g_egl_get("eglInitialize"));
    auto bind_api = reinterpret_cast<PFNEGLBINDAPIPROC>(g_egl_get("eglBindAPI"));
    auto create = reinterpret_cast<PFNEGLCREATECONTEXTPROC>(g_egl_get("eglCreateContext"));
    egl_make_current = reinterpret_cast<PFNEGLMAKECURRENTPROC>(g_egl_get("eglMakeCurrent"));
    egl_destroy = reinterpret_cast<PFNEGLDESTROYCONTEXTPROC>(g_egl_get("eglDestroyContext"));
    egl_terminate = reinterpret_cast<PFNEGLTERMINATEPROC>(g_egl_get("eglTerminate"));
    if (!get_display || !initialize || !bind_api || !create || !egl_make_current || !egl_destroy)
      return "EGL: the surfaceless platform (EGL_MESA_platform_surfaceless) is not available";
    display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) return "EGL: no surfaceless display";
    EGLint major = 0, minor = 0;
    if (!initialize(display, &major, &minor)) {
      display = EGL_NO_DISPLAY;
      return "EGL: eglInitialize failed on the surfaceless display";
    }
    if (!bind_api(EGL_OPENGL_API)) return "EGL: desktop OpenGL API not available";
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context = create(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
    if (context == EGL_NO_CONTEXT) return "EGL: cannot create an OpenGL 3.3 core context without a config";
    if (!egl_make_current(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
      return "EGL: eglMakeCurrent without a surface failed";
    gl::load(&egl_get);
    return {};
  }

  std::string try_osmesa() {
    const char* name = env_or("PROSTATESIM_OSMESA_LIB", "libOSMesa.so.8");
    lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (!lib) return std::string("OSMesa: cannot load ") + name;
    auto create = reinterpret_cast<PfnOsmesaCreate>(dlsym(lib, "OSMesaCreateContextAttribs"));
    osmesa_make_current = reinterpret_cast<PfnOsmesaMakeCurrent>(dlsym(lib, "OSMesaMakeCurrent"));
    osmesa_destroy = reinterpret_cast<PfnOsmesaDestroy>(dlsym(lib, "OSMesaDestroyContext"));
    g_osmesa_get = reinterpret_cast<PfnOsmesaGetProc>(dlsym(lib, "OSMesaGetProcAddress"));
    if (!create || !osmesa_make_current || !osmesa_destroy || !g_osmesa_get)
      return "OSMesa: entry points missing";
    const int attrs[] = {kOsmesaFormat, kOsmesaFormatRgba, kOsmesaDepthBits, 24, kOsmesaStencilBits, 8,
                         kOsmesaAccumBits, 0, kOsmesaProfile, kOsmesaCoreProfile, kOsmesaMajor, 3,
                         kOsmesaMinor, 3, 0};
    osmesa = create(attrs, nullptr);
    if (!osmesa) return "OSMesa: cannot create an OpenGL 3.3 core context";
    // the renderer draws into its own framebuffer; OSMesa still wants a colour buffer bound
    if (!osmesa_make_current(osmesa, osmesa_buffer.data(), 0x1401 /*GL_UNSIGNED_BYTE*/, 4, 4))
      return "OSMesa: OSMesaMakeCurrent failed";
    gl::load(&osmesa_get);
    return {};
  }
};

HeadlessContext::HeadlessContext() {
  const std::string want = env_or("PROSTATESIM_GL", "auto");
  if (want != "auto" && want != "egl" && want != "osmesa")
    throw RenderError("PROSTATESIM_GL=" + want + ": unknown headless OpenGL backend (egl, osmesa or auto)");
  std::string why;
  if (want == "auto" || want == "egl") {
    impl_ = std::make_unique<Impl>();
    const std::string e = impl_->try_egl();
    if (e.empty()) backend_ = "egl";
    else { why = e; impl_.reset(); }
  }
  if (backend_.empty() && (want == "auto" || want == "osmesa")) {
    impl_ = std::make_unique<Impl>();
    const std::string e = impl_->try_osmesa();
    if (e.empty()) backend_ = "osmesa";
    else { why += (why.empty() ? "" : "; ") + e; impl_.reset(); }
  }
  if (backend_.empty())
    throw RenderError("no headless OpenGL 3.3 available (" + why +
                      "); install Mesa's EGL (libegl1, libegl-mesa0) or OSMesa (libosmesa6)");
  const auto* r = reinterpret_cast<const char*>(gl::api.GetString(GL_RENDERER));
  renderer_ = r ? r : "unknown";
}

HeadlessContext::~HeadlessContext() = default;

void HeadlessContext::make_current() {
  if (impl_->context != EGL_NO_CONTEXT)
    impl_->egl_make_current(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context);
  else if (impl_->osmesa)
    impl_->osmesa_make_current(impl_->osmesa, impl_->osmesa_buffer.data(), 0x1401, 4, 4);
}

}  // namespace ps::render
