#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "engine/contract/snapshot.h"
#include "render/gl_api.h"
#include "render/primitive_batches.h"
#include "render/primitives.h"
#include "render/render_error.h"
#include "render/shaders.h"

namespace ps::render {

using gl::api;
using namespace shaders;

Rgba colour_map(double t) {
  static const float c[5][3] = {{0.267f, 0.005f, 0.329f}, {0.229f, 0.322f, 0.546f}, {0.128f, 0.567f, 0.551f},
                                {0.369f, 0.789f, 0.383f}, {0.993f, 0.906f, 0.144f}};
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const float f = static_cast<float>(t - i);
  return {c[i][0] + f * (c[i + 1][0] - c[i][0]), c[i][1] + f * (c[i + 1][1] - c[i][1]),
          c[i][2] + f * (c[i + 1][2] - c[i][2]), 1.0f};
}

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
    const size_t nv = rs.vertex_count();
    sg.vertices.assign(7 * nv, 0.0f);
    sg.positions.assign(3 * nv, 0.0f);
    for (size_t v = 0; v < nv; ++v)
      for (int k = 0; k < 3; ++k)
        sg.positions[3 * v + k] = sg.vertices[7 * v + k] = rs.carry_particles.empty() ? scene_.rest[3 * rs.particles[v] + k] : rs.carry_rest[3 * v + k];
    Gpu::init_surface(sg);
    // sized once: update() only overwrites it
    api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(sg.vertices.size() * sizeof(float)), sg.vertices.data(), GL_DYNAMIC_DRAW);
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
  if (g.isodose.vao) {
    api.DeleteBuffers(1, &g.isodose.vbo);
    api.DeleteBuffers(1, &g.isodose.ibo);
    api.DeleteVertexArrays(1, &g.isodose.vao);
  }
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
    const size_t nv = rs.vertex_count();
    const bool carried = !rs.carry_particles.empty();
    Vec3 sum = Vec3::Zero();
    for (size_t i = 0; i < nv; ++i) {
      float now[3], rest[3];
      if (carried) {
        const Vec3& o = rs.carry_offsets[i];
        for (int k = 0; k < 3; ++k) now[k] = static_cast<float>(o[k]), rest[k] = rs.carry_rest[3 * i + k];
        for (int j = 0; j < 4; ++j) {
          const int p = rs.carry_particles[i][j];
          const float w = rs.carry_weights[i][j];
          for (int k = 0; k < 3; ++k) now[k] += w * x[3 * p + k];
        }
      } else {
        const int p = rs.particles[i];
        for (int k = 0; k < 3; ++k) now[k] = x[3 * p + k], rest[k] = scene_.rest[3 * p + k];
      }
      float d2 = 0.0f;
      for (int k = 0; k < 3; ++k) {
        v[7 * i + k] = sg.positions[3 * i + k] = now[k];
        v[7 * i + 3 + k] = 0.0f;
        const float d = now[k] - rest[k];
        d2 += d * d;
        sum[k] += now[k];
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

  // 3. transparent surfaces, farthest first; back faces then front faces of each (the isodose
  // surface among them, as index kIsodose)
  constexpr size_t kIsodose = static_cast<size_t>(-1);
  std::array<std::pair<double, size_t>, 64> order;
  size_t n = 0;
  if (g.isodose.index_count > 0) order[n++] = {-(g.isodose.centroid - cam.eye).norm(), kIsodose};
  for (size_t s = 0; s < scene_.surfaces.size() && n < order.size(); ++s)
    if (!hidden(s) && opacity(s) < 0.999f) order[n++] = {-(g.surfaces[s].centroid - cam.eye).norm(), s};
  std::sort(order.begin(), order.begin() + static_cast<long>(n));
  auto draw_isodose = [&] {
    const Rgba& c = g.isodose_colour;
    const float col[4] = {c.r, c.g, c.b, c.a};
    api.Uniform1i(api.GetUniformLocation(g.lit_surface, "uUseScalar"), 0);
    api.Uniform4fv(u_colour, 1, col);
    api.BindVertexArray(g.isodose.vao);
    api.DrawElements(GL_TRIANGLES, g.isodose.index_count, GL_UNSIGNED_INT, nullptr);
    api.Uniform1i(api.GetUniformLocation(g.lit_surface, "uUseScalar"), opt.displacement ? 1 : 0);
  };
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
      if (order[i].second == kIsodose) {
        draw_isodose();
        api.CullFace(GL_BACK);
        draw_isodose();
        continue;
      }
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

}  // namespace ps::render
