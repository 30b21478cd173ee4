// The GPU side of the renderer's batches (primitive_batches.h): instance buffers of the unit
// primitives, drawn instanced.
#include "render/primitive_batches.h"

#include <cmath>

namespace ps::render {

using gl::api;

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

void Renderer::Gpu::init_surface(SurfaceGpu& sg) {
  api.GenVertexArrays(1, &sg.vao);
  api.GenBuffers(1, &sg.vbo);
  api.GenBuffers(1, &sg.ibo);
  api.BindVertexArray(sg.vao);
  api.BindBuffer(GL_ARRAY_BUFFER, sg.vbo);
  api.EnableVertexAttribArray(0);
  api.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), nullptr);
  api.EnableVertexAttribArray(1);
  api.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  api.EnableVertexAttribArray(2);
  api.VertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 7 * sizeof(float), reinterpret_cast<void*>(6 * sizeof(float)));
  api.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, sg.ibo);
}

void Renderer::Gpu::init_batch(PrimitiveBatch& b, const PrimitiveMesh& mesh) {
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

void Renderer::Gpu::draw_batch(PrimitiveBatch& b) {
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

}  // namespace ps::render
