// What the renderer batches each frame (internal to render/): instances of the unit sphere,
// cylinder and cone (primitives.h), line and overlay vertices, the scene surfaces' buffers, and
// Renderer::Gpu, the DrawSink that turns a snapshot's draw list into those batches
// (primitive_batches.cpp: the batches' GPU buffers). Needs a current GL context.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "engine/draw/draw_sink.h"
#include "render/gl_api.h"
#include "render/primitives.h"
#include "render/renderer.h"

namespace ps::render {

struct Instance {
  float m[16];  // column-major model matrix
  float c[4];
};
struct LineVertex {
  float p[3];
  float c[4];
};
struct OverlayVertex {
  float p[2];
  uint8_t c[4];
};

inline uint8_t to_byte(float v) { return static_cast<uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); }

// Model matrix that maps the unit primitive's z axis onto `axis` (length = scale along z).
void frame_matrix(const Vec3& origin, const Vec3& axis, double rx, double rz, float* m);

struct PrimitiveBatch {
  unsigned vao = 0, vbo = 0, ibo = 0, inst = 0;
  int index_count = 0;
  size_t capacity = 0;                // instances the instance buffer holds
  std::vector<Instance> items;        // this frame's instances (capacity kept)
};

struct SurfaceGpu {
  unsigned vao = 0, vbo = 0, ibo = 0;
  int index_count = 0;
  std::vector<float> vertices;        // [7 nv]: position [m], normal, displacement [mm]
  std::vector<float> positions;       // [3 nv] [m] (tests, centroid)
  Vec3 centroid = Vec3::Zero();
};

struct Renderer::Gpu : DrawSink {
  unsigned lit_surface = 0, lit_instance = 0, line_prog = 0, overlay_prog = 0;
  std::vector<SurfaceGpu> surfaces;
  SurfaceGpu isodose;                 // the prescription isodose surface (set_isodose), 0 indices: none
  Rgba isodose_colour{1.0f, 0.2f, 0.15f, 0.3f};
  size_t isodose_vbo_floats = 0, isodose_ibo_ints = 0;  // buffer sizes (grown, never shrunk)
  PrimitiveBatch spheres, cylinders, cones;
  // spheres at three levels of detail, chosen per view by their radius on screen: the batch
  // `spheres` (18 x 12) for large ones, these two for small ones (render())
  PrimitiveBatch spheres_mid, spheres_low;
  std::vector<Instance> sphere_list;  // this frame's spheres (update()), split per view
  unsigned line_vao = 0, line_vbo = 0;
  size_t line_capacity = 0;
  std::vector<LineVertex> lines;
  unsigned overlay_vao = 0, overlay_vbo = 0;
  size_t overlay_capacity = 0;
  std::vector<OverlayVertex> overlay;
  std::vector<char> text_scratch = std::vector<char>(64 * 1024);
  bool show_forces = true;
  // per-batch list of force-arrow instances so they can be hidden without re-batching
  size_t sphere_force_begin = 0;

  // DrawSink: the instruments' description, batched into instances
  void segment(const Vec3& a, const Vec3& b, Rgba c, DrawRole) override {
    lines.push_back({{float(a.x()), float(a.y()), float(a.z())}, {c.r, c.g, c.b, c.a}});
    lines.push_back({{float(b.x()), float(b.y()), float(b.z())}, {c.r, c.g, c.b, c.a}});
  }
  void capsule(const Vec3& a, const Vec3& b, double r, Rgba c, DrawRole) override {
    cylinder(a, b, r, c);
    sphere_at(a, r, c);
    sphere_at(b, r, c);
  }
  void cylinder(const Vec3& a, const Vec3& b, double r, Rgba c) {
    Instance in{};
    std::memcpy(in.c, &c, sizeof in.c);
    frame_matrix(a, b - a, r, (b - a).norm(), in.m);
    cylinders.items.push_back(in);
  }
  void sphere(const Vec3& centre, double r, Rgba c, DrawRole) override { sphere_at(centre, r, c); }
  void arrow(const Vec3& from, const Vec3& vec, Rgba c, DrawRole role) override {
    if (role == DrawRole::Force && !show_forces) return;
    const double len = vec.norm();
    if (len < 1e-6) return;
    const double shaft_r = std::clamp(0.03 * len, 0.4e-3, 1.2e-3);
    const double head = std::min(0.3 * len, 6.0 * shaft_r);
    const Vec3 dir = vec / len;
    Instance s{};
    std::memcpy(s.c, &c, sizeof s.c);
    frame_matrix(from, dir * (len - head), shaft_r, len - head, s.m);
    cylinders.items.push_back(s);
    Instance h{};
    std::memcpy(h.c, &c, sizeof h.c);
    frame_matrix(from + dir * (len - head), dir * head, 2.5 * shaft_r, head, h.m);
    cones.items.push_back(h);
  }
  void sphere_at(const Vec3& p, double r, Rgba c) {
    Instance in{};
    std::memcpy(in.c, &c, sizeof in.c);
    frame_matrix(p, Vec3::UnitZ(), r, r, in.m);
    sphere_list.push_back(in);
  }

  // the GPU side of a batch: the primitive's mesh, an instance buffer of 256 to begin with
  void init_batch(PrimitiveBatch& b, const PrimitiveMesh& mesh);
  // a surface's vertex array: position, normal, displacement interleaved (SurfaceGpu::vertices);
  // leaves it bound with its vertex and index buffers (their data is the caller's)
  static void init_surface(SurfaceGpu& sg);
  // uploads this frame's instances (growing the buffer when they outgrow it) and draws them
  void draw_batch(PrimitiveBatch& b);

  // streams a vector into a dynamic buffer that only grows
  template <class V>
  void stream(unsigned vbo, size_t& capacity, const std::vector<V>& data) {
    gl::api.BindBuffer(GL_ARRAY_BUFFER, vbo);
    if (data.size() > capacity) {
      capacity = std::max<size_t>(data.size(), 2 * capacity);
      gl::api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(capacity * sizeof(V)), nullptr, GL_DYNAMIC_DRAW);
    }
    gl::api.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(data.size() * sizeof(V)), data.data());
  }
};

}  // namespace ps::render
