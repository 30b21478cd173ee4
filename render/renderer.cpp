#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "engine/contract/snapshot.h"
#include "render/gl_api.h"
#include "render/primitives.h"
#include "render/render_error.h"

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

using gl::api;

namespace {

// ---- shaders ---------------------------------------------------------------------------------
constexpr const char* kColourMapGlsl = R"(
vec3 cmap(float t) {
  const vec3 c0 = vec3(0.267, 0.005, 0.329), c1 = vec3(0.229, 0.322, 0.546),
             c2 = vec3(0.128, 0.567, 0.551), c3 = vec3(0.369, 0.789, 0.383), c4 = vec3(0.993, 0.906, 0.144);
  t = clamp(t, 0.0, 1.0) * 4.0;
  if (t < 1.0) return mix(c0, c1, t);
  if (t < 2.0) return mix(c1, c2, t - 1.0);
  if (t < 3.0) return mix(c2, c3, t - 2.0);
  return mix(c3, c4, t - 3.0);
}
)";

constexpr const char* kSurfaceVs = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aScalar;
uniform mat4 uViewProj;
uniform vec4 uColour;
uniform int uUseScalar;
uniform float uScalarMax;
out vec3 vPos; out vec3 vNormal; out vec4 vColour;
void main() {
  vPos = aPos; vNormal = aNormal;
  vColour = uUseScalar == 1 ? vec4(cmap(aScalar / uScalarMax), uColour.a) : uColour;
  gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

constexpr const char* kInstanceVs = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 3) in vec4 iM0;
layout(location = 4) in vec4 iM1;
layout(location = 5) in vec4 iM2;
layout(location = 6) in vec4 iM3;
layout(location = 7) in vec4 iColour;
uniform mat4 uViewProj;
out vec3 vPos; out vec3 vNormal; out vec4 vColour;
void main() {
  mat4 m = mat4(iM0, iM1, iM2, iM3);
  vec4 w = m * vec4(aPos, 1.0);
  vPos = w.xyz;
  vNormal = transpose(inverse(mat3(m))) * aNormal;
  vColour = iColour;
  gl_Position = uViewProj * w;
}
)";

// Headlight plus a key light from above-anterior; two-sided; transparent surfaces get a rim
// (more opaque where seen edge-on) so an organ's outline reads through the fat.
constexpr const char* kLitFs = R"(
in vec3 vPos; in vec3 vNormal; in vec4 vColour;
uniform vec3 uEye;
uniform float uRim;
out vec4 oColour;
void main() {
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(uEye - vPos);
  vec3 key = normalize(vec3(0.35, 0.45, 0.82));
  float nv = max(dot(n, v), 0.0);
  float diff = 0.55 * nv + 0.35 * max(dot(n, key), 0.0);
  // powers by multiplication: pow() costs a software rasteriser exp2(log2()) per pixel
  float s = max(dot(n, normalize(key + v)), 0.0);
  s *= s; s *= s; s *= s; s *= s; s *= s;  // s^32
  float spec = 0.22 * s;
  vec3 rgb = vColour.rgb * (0.28 + diff) + vec3(spec);
  float a = vColour.a;
  float e = 1.0 - nv;
  if (a < 0.999) a = clamp(a + uRim * (1.0 - a) * e * e * e, 0.0, 1.0);
  oColour = vec4(rgb, a);
}
)";

constexpr const char* kLineVs = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec4 aColour;
uniform mat4 uViewProj;
out vec4 vColour;
void main() { vColour = aColour; gl_Position = uViewProj * vec4(aPos, 1.0); }
)";
constexpr const char* kFlatFs = R"(
in vec4 vColour;
out vec4 oColour;
void main() { oColour = vColour; }
)";
constexpr const char* kOverlayVs = R"(
layout(location = 0) in vec2 aPos;
layout(location = 1) in vec4 aColour;
uniform vec2 uScreen;
out vec4 vColour;
void main() {
  vColour = aColour;
  gl_Position = vec4(2.0 * aPos.x / uScreen.x - 1.0, 1.0 - 2.0 * aPos.y / uScreen.y, 0.0, 1.0);
}
)";

unsigned compile(GLenum type, const std::string& src) {
  const unsigned s = api.CreateShader(type);
  const std::string full = std::string("#version 330 core\n") + (type == GL_VERTEX_SHADER ? kColourMapGlsl : "") + src;
  const char* p = full.c_str();
  api.ShaderSource(s, 1, &p, nullptr);
  api.CompileShader(s);
  int ok = 0;
  api.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    api.GetShaderInfoLog(s, sizeof log, nullptr, log);
    throw RenderError(std::string("shader compile failed: ") + log);
  }
  return s;
}

unsigned link(const char* vs, const char* fs) {
  const unsigned v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
  const unsigned p = api.CreateProgram();
  api.AttachShader(p, v);
  api.AttachShader(p, f);
  api.LinkProgram(p);
  api.DeleteShader(v);
  api.DeleteShader(f);
  int ok = 0;
  api.GetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    api.GetProgramInfoLog(p, sizeof log, nullptr, log);
    throw RenderError(std::string("shader link failed: ") + log);
  }
  return p;
}

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

uint8_t to_byte(float v) { return static_cast<uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); }

// Model matrix that maps the unit primitive's z axis onto `axis` (length = scale along z).
void frame_matrix(const Vec3& origin, const Vec3& axis, double rx, double rz, float* m) {
  const double len = axis.norm();
  const Vec3 w = len > 1e-12 ? Vec3(axis / len) : Vec3::UnitZ();
  const Vec3 helper = std::abs(w.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
  const Vec3 u = helper.cross(w).normalized(), v = w.cross(u);
  const Vec3 cols[3] = {u * rx, v * rx, w * rz};
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m[4 * c + r] = static_cast<float>(cols[c][r]);
    m[4 * c + 3] = 0.0f;
  }
  for (int r = 0; r < 3; ++r) m[12 + r] = static_cast<float>(origin[r]);
  m[15] = 1.0f;
}

}  // namespace

Rgba colour_map(double t) {
  static const float c[5][3] = {{0.267f, 0.005f, 0.329f}, {0.229f, 0.322f, 0.546f}, {0.128f, 0.567f, 0.551f},
                                {0.369f, 0.789f, 0.383f}, {0.993f, 0.906f, 0.144f}};
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const float f = static_cast<float>(t - i);
  return {c[i][0] + f * (c[i + 1][0] - c[i][0]), c[i][1] + f * (c[i + 1][1] - c[i][1]),
          c[i][2] + f * (c[i + 1][2] - c[i][2]), 1.0f};
}

// ---- GPU side ----------------------------------------------------------------------------------

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

  void init_batch(PrimitiveBatch& b, const PrimitiveMesh& mesh) {
    api.GenVertexArrays(1, &b.vao);
    api.GenBuffers(1, &b.vbo);
    api.GenBuffers(1, &b.ibo);
    api.GenBuffers(1, &b.inst);
    api.BindVertexArray(b.vao);
    api.BindBuffer(GL_ARRAY_BUFFER, b.vbo);
    api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(float)), mesh.vertices.data(), GL_STATIC_DRAW);
    api.EnableVertexAttribArray(0);
    api.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    api.EnableVertexAttribArray(1);
    api.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
    api.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.ibo);
    api.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)), mesh.indices.data(), GL_STATIC_DRAW);
    b.index_count = static_cast<int>(mesh.indices.size());
    b.capacity = 256;
    api.BindBuffer(GL_ARRAY_BUFFER, b.inst);
    api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(b.capacity * sizeof(Instance)), nullptr, GL_DYNAMIC_DRAW);
    for (int k = 0; k < 5; ++k) {
      api.EnableVertexAttribArray(3 + k);
      api.VertexAttribPointer(3 + k, 4, GL_FLOAT, GL_FALSE, sizeof(Instance), reinterpret_cast<void*>(k * 4 * sizeof(float)));
      api.VertexAttribDivisor(3 + k, 1);
    }
    api.BindVertexArray(0);
    b.items.reserve(b.capacity);
  }

  void draw_batch(PrimitiveBatch& b) {
    if (b.items.empty()) return;
    api.BindBuffer(GL_ARRAY_BUFFER, b.inst);
    if (b.items.size() > b.capacity) {  // grows rarely (more needles than ever before)
      while (b.capacity < b.items.size()) b.capacity *= 2;
      api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(b.capacity * sizeof(Instance)), nullptr, GL_DYNAMIC_DRAW);
    }
    api.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(b.items.size() * sizeof(Instance)), b.items.data());
    api.BindVertexArray(b.vao);
    api.DrawElementsInstanced(GL_TRIANGLES, b.index_count, GL_UNSIGNED_INT, nullptr, static_cast<GLsizei>(b.items.size()));
  }

  // streams a vector into a dynamic buffer that only grows
  template <class V>
  void stream(unsigned vbo, size_t& capacity, const std::vector<V>& data) {
    api.BindBuffer(GL_ARRAY_BUFFER, vbo);
    if (data.size() > capacity) {
      capacity = std::max<size_t>(data.size(), 2 * capacity);
      api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(capacity * sizeof(V)), nullptr, GL_DYNAMIC_DRAW);
    }
    api.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(data.size() * sizeof(V)), data.data());
  }
};

Renderer::Renderer(RenderScene scene) : scene_(std::move(scene)), gpu_(std::make_unique<Gpu>()) {
  if (!gl::loaded()) throw RenderError("renderer created without a current OpenGL context");
  Gpu& g = *gpu_;
  g.lit_surface = link(kSurfaceVs, kLitFs);
  g.lit_instance = link(kInstanceVs, kLitFs);
  g.line_prog = link(kLineVs, kFlatFs);
  g.overlay_prog = link(kOverlayVs, kFlatFs);
  g.surfaces.resize(scene_.surfaces.size());
  for (size_t s = 0; s < scene_.surfaces.size(); ++s) {
    const RenderSurface& rs = scene_.surfaces[s];
    SurfaceGpu& sg = g.surfaces[s];
    const size_t nv = rs.particles.size();
    sg.vertices.assign(7 * nv, 0.0f);
    sg.positions.assign(3 * nv, 0.0f);
    for (size_t v = 0; v < nv; ++v)
      for (int k = 0; k < 3; ++k) sg.positions[3 * v + k] = sg.vertices[7 * v + k] = scene_.rest[3 * rs.particles[v] + k];
    api.GenVertexArrays(1, &sg.vao);
    api.GenBuffers(1, &sg.vbo);
    api.GenBuffers(1, &sg.ibo);
    api.BindVertexArray(sg.vao);
    api.BindBuffer(GL_ARRAY_BUFFER, sg.vbo);
    // sized once: update() only overwrites it
    api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(sg.vertices.size() * sizeof(float)), sg.vertices.data(), GL_DYNAMIC_DRAW);
    api.EnableVertexAttribArray(0);
    api.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), nullptr);
    api.EnableVertexAttribArray(1);
    api.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
    api.EnableVertexAttribArray(2);
    api.VertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 7 * sizeof(float), reinterpret_cast<void*>(6 * sizeof(float)));
    api.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, sg.ibo);
    api.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(rs.indices.size() * sizeof(uint32_t)), rs.indices.data(), GL_STATIC_DRAW);
    sg.index_count = static_cast<int>(rs.indices.size());
  }
  g.init_batch(g.spheres, unit_sphere(18, 12));
  // the coarse spheres are scaled so that their outline (an N-gon at the equator) has the area of
  // the sphere's disc: an inscribed polygon would shrink the small seed and target dots
  auto area_true_sphere = [](int slices, int stacks) {
    PrimitiveMesh m = unit_sphere(slices, stacks);
    const double kPi = 3.14159265358979323846;
    const float k = static_cast<float>(std::sqrt(kPi / (0.5 * slices * std::sin(2 * kPi / slices))));
    for (size_t v = 0; v < m.vertices.size(); v += 6)
      for (int d = 0; d < 3; ++d) m.vertices[v + d] *= k;
    return m;
  };
  g.init_batch(g.spheres_mid, area_true_sphere(10, 6));
  g.init_batch(g.spheres_low, area_true_sphere(6, 4));
  g.sphere_list.reserve(g.spheres.capacity);
  g.init_batch(g.cylinders, unit_cylinder(20));
  g.init_batch(g.cones, unit_cone(20));
  api.GenVertexArrays(1, &g.line_vao);
  api.GenBuffers(1, &g.line_vbo);
  api.BindVertexArray(g.line_vao);
  api.BindBuffer(GL_ARRAY_BUFFER, g.line_vbo);
  g.line_capacity = 1024;
  api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(g.line_capacity * sizeof(LineVertex)), nullptr, GL_DYNAMIC_DRAW);
  api.EnableVertexAttribArray(0);
  api.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex), nullptr);
  api.EnableVertexAttribArray(1);
  api.VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(LineVertex), reinterpret_cast<void*>(3 * sizeof(float)));
  api.GenVertexArrays(1, &g.overlay_vao);
  api.GenBuffers(1, &g.overlay_vbo);
  api.BindVertexArray(g.overlay_vao);
  api.BindBuffer(GL_ARRAY_BUFFER, g.overlay_vbo);
  g.overlay_capacity = 8192;
  api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(g.overlay_capacity * sizeof(OverlayVertex)), nullptr, GL_DYNAMIC_DRAW);
  api.EnableVertexAttribArray(0);
  api.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex), nullptr);
  api.EnableVertexAttribArray(1);
  api.VertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(OverlayVertex), reinterpret_cast<void*>(2 * sizeof(float)));
  api.BindVertexArray(0);
  g.lines.reserve(g.line_capacity);
  g.overlay.reserve(g.overlay_capacity);
}

Renderer::~Renderer() {
  if (!gpu_ || !gl::loaded()) return;
  Gpu& g = *gpu_;
  for (auto& s : g.surfaces) {
    api.DeleteBuffers(1, &s.vbo);
    api.DeleteBuffers(1, &s.ibo);
    api.DeleteVertexArrays(1, &s.vao);
  }
  for (PrimitiveBatch* b : {&g.spheres, &g.spheres_mid, &g.spheres_low, &g.cylinders, &g.cones}) {
    api.DeleteBuffers(1, &b->vbo);
    api.DeleteBuffers(1, &b->ibo);
    api.DeleteBuffers(1, &b->inst);
    api.DeleteVertexArrays(1, &b->vao);
  }
  api.DeleteBuffers(1, &g.line_vbo);
  api.DeleteVertexArrays(1, &g.line_vao);
  api.DeleteBuffers(1, &g.overlay_vbo);
  api.DeleteVertexArrays(1, &g.overlay_vao);
  for (unsigned p : {g.lit_surface, g.lit_instance, g.line_prog, g.overlay_prog}) api.DeleteProgram(p);
}

const std::vector<float>& Renderer::surface_vertices(int s) const { return gpu_->surfaces.at(s).positions; }

void Renderer::update(const Snapshot& snap) {
  if (snap.x.size() != 3 * static_cast<size_t>(scene_.particle_count))
    throw RenderError("snapshot has " + std::to_string(snap.x.size() / 3) + " particles, the scene " +
                      std::to_string(scene_.particle_count));
  Gpu& g = *gpu_;
  const float* x = snap.x.data();
  for (size_t s = 0; s < scene_.surfaces.size(); ++s) {
    const RenderSurface& rs = scene_.surfaces[s];
    SurfaceGpu& sg = g.surfaces[s];
    float* v = sg.vertices.data();
    const size_t nv = rs.particles.size();
    Vec3 sum = Vec3::Zero();
    for (size_t i = 0; i < nv; ++i) {
      const int p = rs.particles[i];
      float d2 = 0.0f;
      for (int k = 0; k < 3; ++k) {
        v[7 * i + k] = sg.positions[3 * i + k] = x[3 * p + k];
        v[7 * i + 3 + k] = 0.0f;
        const float d = x[3 * p + k] - scene_.rest[3 * p + k];
        d2 += d * d;
        sum[k] += x[3 * p + k];
      }
      v[7 * i + 6] = std::sqrt(d2) * 1e3f;  // [mm]
    }
    sg.centroid = nv ? Vec3(sum / static_cast<double>(nv)) : Vec3::Zero();
    // area-weighted vertex normals
    const auto& ix = rs.indices;
    for (size_t f = 0; f + 2 < ix.size(); f += 3) {
      const float* a = &v[7 * ix[f]];
      const float* b = &v[7 * ix[f + 1]];
      const float* c = &v[7 * ix[f + 2]];
      const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
      const float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) v[7 * ix[f + k] + 3 + j] += n[j];
    }
    api.BindBuffer(GL_ARRAY_BUFFER, sg.vbo);
    api.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(sg.vertices.size() * sizeof(float)), sg.vertices.data());
  }
  // instruments and tissue markers, batched into instances (vectors keep their capacity)
  g.sphere_list.clear();
  g.cylinders.items.clear();
  g.cones.items.clear();
  g.lines.clear();
  for (const RenderMarkers& mk : scene_.markers)
    for (int p : mk.particles)
      g.sphere_at(Vec3(x[3 * p], x[3 * p + 1], x[3 * p + 2]), mk.radius, mk.colour);
  for (const RenderTube& t : scene_.tubes) {
    Vec3 prev = Vec3::Zero();
    for (size_t k = 0; k < t.particles.size(); ++k) {
      Vec3 q = t.offsets[k];
      for (int j = 0; j < 4; ++j) {
        const int p = t.particles[k][j];
        q += t.weights[k][j] * Vec3(x[3 * p], x[3 * p + 1], x[3 * p + 2]);
      }
      // a cylinder per segment and one sphere per joint (capsule() would draw each inner joint's
      // sphere twice: half the tube's triangles, the same pixels)
      if (k > 0) g.cylinder(prev, q, t.radius, t.colour);
      g.sphere_at(q, t.radius, t.colour);
      prev = q;
    }
  }
  snap.draw.replay(g);
  tools_.assign(snap.tools.begin(), snap.tools.end());
  last_time_ = snap.time;
}

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
      if (t.kind == ToolReadout::Needle && t.active) {
        std::snprintf(line, sizeof line, "needle %s: depth %.1f mm, force %.2f N", t.name.data(), t.depth * 1e3, t.force);
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

void Renderer::render(const Camera& cam, int width, int height, const RenderOptions& opt) {
  if (width <= 0 || height <= 0) return;
  Gpu& g = *gpu_;
  g.show_forces = opt.force_arrows;
  api.Viewport(opt.viewport_x, opt.viewport_y, width, height);
  api.Scissor(opt.viewport_x, opt.viewport_y, width, height);
  api.Enable(GL_SCISSOR_TEST);
  api.ClearColor(opt.background.r, opt.background.g, opt.background.b, 1.0f);
  api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  api.Disable(GL_SCISSOR_TEST);
  api.Enable(GL_DEPTH_TEST);
  api.DepthFunc(GL_LEQUAL);
  api.Enable(GL_MULTISAMPLE);
  api.Disable(GL_CULL_FACE);
  api.Disable(GL_BLEND);
  api.DepthMask(GL_TRUE);

  const Mat4f vp = cam.projection(static_cast<double>(width) / height) * cam.view();
  const float eye[3] = {float(cam.eye.x()), float(cam.eye.y()), float(cam.eye.z())};
  auto opacity = [&](size_t s) {
    return s < opt.opacity.size() ? std::clamp(opt.opacity[s], 0.0f, 1.0f) : scene_.surfaces[s].colour.a;
  };
  auto hidden = [&](size_t s) { return (s < opt.hidden.size() && opt.hidden[s]) || opacity(s) <= 0.0f; };

  // 1. opaque surfaces
  api.UseProgram(g.lit_surface);
  api.UniformMatrix4fv(api.GetUniformLocation(g.lit_surface, "uViewProj"), 1, GL_FALSE, vp.data());
  api.Uniform3fv(api.GetUniformLocation(g.lit_surface, "uEye"), 1, eye);
  api.Uniform1i(api.GetUniformLocation(g.lit_surface, "uUseScalar"), opt.displacement ? 1 : 0);
  api.Uniform1f(api.GetUniformLocation(g.lit_surface, "uScalarMax"), static_cast<float>(std::max(1e-6, opt.displacement_max_mm)));
  api.Uniform1f(api.GetUniformLocation(g.lit_surface, "uRim"), 0.6f);
  const int u_colour = api.GetUniformLocation(g.lit_surface, "uColour");
  auto draw_surface = [&](size_t s, float a) {
    const Rgba& c = scene_.surfaces[s].colour;
    const float col[4] = {c.r, c.g, c.b, a};
    api.Uniform4fv(u_colour, 1, col);
    api.BindVertexArray(g.surfaces[s].vao);
    api.DrawElements(GL_TRIANGLES, g.surfaces[s].index_count, GL_UNSIGNED_INT, nullptr);
  };
  for (size_t s = 0; s < scene_.surfaces.size(); ++s)
    if (!hidden(s) && opacity(s) >= 0.999f) draw_surface(s, 1.0f);

  // 2. instruments, markers, urethra (opaque instances) and lines
  api.UseProgram(g.lit_instance);
  api.UniformMatrix4fv(api.GetUniformLocation(g.lit_instance, "uViewProj"), 1, GL_FALSE, vp.data());
  api.Uniform3fv(api.GetUniformLocation(g.lit_instance, "uEye"), 1, eye);
  api.Uniform1f(api.GetUniformLocation(g.lit_instance, "uRim"), 0.0f);
  // closed, outward-wound primitives (the cylinder is capped): their back faces are never seen, and
  // culling them before rasterisation halves the triangles the (software) rasteriser sets up
  api.Enable(GL_CULL_FACE);
  api.CullFace(GL_BACK);
  {
    // level of detail: an N-slice polygon departs from its circle by r (1 - cos(pi / N)) on
    // screen; 6 x 4 below 3 px of radius and 10 x 6 below 10 px (an even number of stacks, so the
    // equator is a ring) keep that under 0.5 px, while the 432 triangles of the 18 x 12 sphere,
    // most of them under a pixel on the urethra's and the needle's joints, cost a software
    // rasteriser ~10 ms CPU per 720p frame with 4x multisampling (docs/rendering.md)
    const double px_per_rad = 0.5 * height / std::tan(0.5 * cam.fov_y_deg * 3.14159265358979323846 / 180.0);
    g.spheres.items.clear();
    g.spheres_mid.items.clear();
    g.spheres_low.items.clear();
    for (const Instance& in : g.sphere_list) {
      const Vec3 c(in.m[12], in.m[13], in.m[14]);
      const double r = Vec3(in.m[0], in.m[1], in.m[2]).norm();
      const double dist = (c - cam.eye).dot((cam.target - cam.eye).normalized());  // depth along the view axis [m]
      const double r_px = dist > cam.near_m ? r / dist * px_per_rad : 1e9;
      (r_px < 3.0 ? g.spheres_low : r_px < 10.0 ? g.spheres_mid : g.spheres).items.push_back(in);
    }
  }
  g.draw_batch(g.spheres);
  g.draw_batch(g.spheres_mid);
  g.draw_batch(g.spheres_low);
  g.draw_batch(g.cylinders);
  g.draw_batch(g.cones);
  api.Disable(GL_CULL_FACE);
  if (!g.lines.empty()) {
    api.UseProgram(g.line_prog);
    api.UniformMatrix4fv(api.GetUniformLocation(g.line_prog, "uViewProj"), 1, GL_FALSE, vp.data());
    g.stream(g.line_vbo, g.line_capacity, g.lines);
    api.BindVertexArray(g.line_vao);
    api.DrawArrays(GL_LINES, 0, static_cast<GLsizei>(g.lines.size()));
  }

  // 3. transparent surfaces, farthest first; back faces then front faces of each
  std::array<std::pair<double, size_t>, 64> order;
  size_t n = 0;
  for (size_t s = 0; s < scene_.surfaces.size() && n < order.size(); ++s)
    if (!hidden(s) && opacity(s) < 0.999f) order[n++] = {-(g.surfaces[s].centroid - cam.eye).norm(), s};
  std::sort(order.begin(), order.begin() + static_cast<long>(n));
  if (n) {
    api.UseProgram(g.lit_surface);
    api.Enable(GL_BLEND);
    api.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    api.DepthMask(GL_FALSE);
    api.Enable(GL_CULL_FACE);
    for (size_t i = 0; i < n; ++i) {
      // the enclosing fat's far walls lie behind every organ and add only a faint tint, yet they
      // cover most of the frame: on a software rasteriser that blended full-screen pass cost
      // ~9 of ~39 ms CPU per 720p frame (docs/rendering.md), so the fat shows its near side only
      api.CullFace(GL_FRONT);
      if (scene_.surfaces[order[i].second].kind != OrganKind::Fat) draw_surface(order[i].second, opacity(order[i].second));
      api.CullFace(GL_BACK);
      draw_surface(order[i].second, opacity(order[i].second));
    }
    api.Disable(GL_CULL_FACE);
    api.DepthMask(GL_TRUE);
  }

  // 4. overlay
  if (opt.hud) draw_hud(width, height, opt);
  if (!g.overlay.empty()) {
    api.Disable(GL_DEPTH_TEST);
    api.Enable(GL_BLEND);
    api.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    api.UseProgram(g.overlay_prog);
    api.Uniform2f(api.GetUniformLocation(g.overlay_prog, "uScreen"), static_cast<float>(width), static_cast<float>(height));
    g.stream(g.overlay_vbo, g.overlay_capacity, g.overlay);
    api.BindVertexArray(g.overlay_vao);
    api.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(g.overlay.size()));
    g.overlay.clear();
    api.Enable(GL_DEPTH_TEST);
  }
  api.Disable(GL_BLEND);
  api.BindVertexArray(0);
  api.UseProgram(0);
}

// ---- offscreen target ----------------------------------------------------------------------------

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
