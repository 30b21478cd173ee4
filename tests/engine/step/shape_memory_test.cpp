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
  double worst = 0, scale = 0;
  for (int p = 0; p < m->particle_count(); p += 7) {
    for (int a = 0; a < 3; ++a) {
      const double h = 1e-7, x0 = s.x[p][a];
      s.x[p][a] = x0 + h;
      const double ep = shape_energy(*m, s);
      s.x[p][a] = x0 - h;
      const double em = shape_energy(*m, s);
      s.x[p][a] = x0;
      const double fd = -(ep - em) / (2 * h);
      worst = std::max(worst, std::abs(fd - force[p][a]));
      scale = std::max(scale, std::abs(force[p][a]));
    }
  }
  EXPECT_LE(worst, 1e-5 * scale);
}

}  // namespace
}  // namespace ps
