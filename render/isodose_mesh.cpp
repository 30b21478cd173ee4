// Renderer::set_isodose: the implant's prescription isodose surface (engine/dosimetry/isodose.h)
// uploaded as one more translucent surface (render() sorts it with the others). Its buffers grow
// to the largest surface seen and are rewritten in place after that.
#include "render/gl_api.h"
#include "render/primitive_batches.h"
#include "render/renderer.h"

namespace ps::render {

using gl::api;

void Renderer::set_isodose(const dosimetry::IsoSurface& s, Rgba colour) {
  Gpu& g = *gpu_;
  SurfaceGpu& sg = g.isodose;
  g.isodose_colour = colour;
  sg.index_count = 0;
  if (s.faces.empty()) return;
  const size_t nv = s.vertices_mm.size();
  sg.vertices.resize(7 * nv);
  Vec3 sum = Vec3::Zero();
  for (size_t v = 0; v < nv; ++v) {
    const Vec3 p = 1e-3 * s.vertices_mm[v];  // [m]
    sum += p;
    for (int k = 0; k < 3; ++k) {
      sg.vertices[7 * v + k] = static_cast<float>(p[k]);
      sg.vertices[7 * v + 3 + k] = static_cast<float>(s.normals[v][k]);
    }
    sg.vertices[7 * v + 6] = 0.0f;
  }
  sg.centroid = sum / static_cast<double>(nv);
  std::vector<uint32_t> idx;
  idx.reserve(3 * s.faces.size());
  for (const auto& f : s.faces)
    for (int k = 0; k < 3; ++k) idx.push_back(static_cast<uint32_t>(f[k]));
  if (!sg.vao) Gpu::init_surface(sg);
  api.BindVertexArray(sg.vao);
  api.BindBuffer(GL_ARRAY_BUFFER, sg.vbo);
  if (sg.vertices.size() > g.isodose_vbo_floats) {
    g.isodose_vbo_floats = sg.vertices.size();
    api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(sg.vertices.size() * sizeof(float)), sg.vertices.data(), GL_DYNAMIC_DRAW);
  } else {
    api.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(sg.vertices.size() * sizeof(float)), sg.vertices.data());
  }
  api.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, sg.ibo);
  if (idx.size() > g.isodose_ibo_ints) {
    g.isodose_ibo_ints = idx.size();
    api.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(uint32_t)), idx.data(), GL_DYNAMIC_DRAW);
  } else {
    api.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(idx.size() * sizeof(uint32_t)), idx.data());
  }
  api.BindVertexArray(0);
  sg.index_count = static_cast<int>(idx.size());
}

}  // namespace ps::render
