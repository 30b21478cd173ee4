// The OpenGL 3.3 core renderer: tissue surfaces deformed by each Snapshot, instruments from the
// snapshot's DrawList (tools describe themselves; the renderer knows no tool), lesion and target
// markers, the urethra, optional displacement colouring with a colour bar, force arrows, a small
// heads-up display. The same code draws into the GLFW window and into an offscreen framebuffer.
// Needs a current GL context with the table of gl_api.h loaded. renderer.cpp updates and draws;
// its programs are in shaders.cpp, its batches in primitive_batches.{h,cpp}, the 2D overlay and
// HUD in hud.cpp; headless views draw into an OffscreenTarget (offscreen_target.h).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/contract/snapshot.h"
#include "engine/dosimetry/isodose.h"
#include "engine/draw/draw_sink.h"
#include "render/camera.h"
#include "render/render_scene.h"

namespace ps::render {

struct RenderOptions {
  std::vector<float> opacity;          // per scene surface [0,1]; empty or short: the defaults
  std::vector<uint8_t> hidden;         // per scene surface, 1 = not drawn
  bool displacement = false;           // colour surfaces by |x - rest| [mm] with a colour bar
  double displacement_max_mm = 5.0;    // top of the colour scale [mm]
  bool force_arrows = true;            // DrawRole::Force primitives
  bool hud = true;                     // title, time, needle read-out, legend
  std::string title;                   // e.g. scene and view name
  Rgba background{0.09f, 0.10f, 0.12f, 1.0f};
  int viewport_x = 0, viewport_y = 0;  // lower-left corner of the view in the framebuffer [px]
};

class Renderer {
 public:
  explicit Renderer(RenderScene scene);  // compiles shaders, allocates every surface buffer once
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Copies positions into the surface buffers (glBufferSubData into buffers sized at
  // construction: no reallocation), recomputes normals and displacements, batches the draw list.
  // Throws RenderError if the snapshot's particle count does not match the scene.
  void update(const Snapshot& snap);
  // Draws into the bound framebuffer, viewport (viewport_x, viewport_y, width, height).
  void render(const Camera& cam, int width, int height, const RenderOptions& opt);

  // The prescription isodose surface of the implant (engine/dosimetry/isodose.h, millimetres),
  // drawn translucent with the transparent surfaces until replaced; an empty one removes it
  // (isodose_mesh.cpp).
  void set_isodose(const dosimetry::IsoSurface& surface_mm, Rgba colour = {1.0f, 0.2f, 0.15f, 0.3f});

  // 2D overlay in pixels (origin top-left), drawn at the end of the next render(), then cleared.
  void text(float x, float y, const std::string& s, Rgba c, float scale = 2.0f);
  void rect(float x, float y, float w, float h, Rgba c);
  static float text_width(const std::string& s, float scale = 2.0f);

  const RenderScene& scene() const { return scene_; }
  // Surface vertices after the last update [m] (tests).
  const std::vector<float>& surface_vertices(int s) const;

  struct Gpu;

 private:
  void draw_hud(int width, int height, const RenderOptions& opt);
  RenderScene scene_;
  std::unique_ptr<Gpu> gpu_;
  std::vector<ToolReadout> tools_;    // read-outs of the last update (capacity kept)
  double last_time_ = 0.0;
};

// Viridis-like colour of t in [0, 1] (displacement colour bar; also in the shader).
Rgba colour_map(double t);

}  // namespace ps::render
