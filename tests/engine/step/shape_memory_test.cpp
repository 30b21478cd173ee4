// The default redistribution makes the shape-memory force the exact gradient of
// E = sum_p 1/2 k_e |P*_p - P_p|^2 (checked by finite differences on a deformed cylinder).
#include <gtest/gtest.h>

#include <random>

#include "engine/step/stages.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

double shape_energy(const Model& m, State& s) {
  for (auto& f : s.f) f.setZero();
  add_shape_memory_forces(m, s);
  double e = 0;
  for (int p = 0; p < m.particle_count(); ++p) e += 0.5 * m.k_e[p] * (s.attractor[p] - s.x[p]).squaredNorm();
  return e;
}

TEST(ShapeMemoryForce, IsTheGradientOfTheShapeEnergy) {
  auto m = test::compile_text(
      "name: cyl\nmaterials: {soft: {young_kpa: 60}}\ncomponents:\n"
      "  - {name: c, material: soft, spacing_mm: 6, cylinder: {radius_mm: 12, length_mm: 30}}\n");
  State s = make_state(*m);
  std::mt19937 rng(11);
  std::normal_distribution<double> N(0.0, 0.002);
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
  shape_energy(*m, s);
  const std::vector<Vec3> force = s.f;
  const auto [worst, scale] = test::gradient_mismatch(s, force, 7, [&](State& st) { return shape_energy(*m, st); });
  EXPECT_LE(worst, 1e-5 * scale);
}

}  // namespace
}  // namespace ps
