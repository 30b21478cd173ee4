// Shell-model force (engine/step/shell_elastic.cpp, engine/model/shell_elements.cpp): the exact
// gradient of its energy (membrane and hinges), zero at rest and for rigid motions, momentum
// conserving, plate theory's energy for an equibiaxial strain, and a pressurised closed cylinder
// against the thin-shell solution (hoop and axial stress: Delta R = p R^2 (1 - nu/2) / (E t)).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/model/shell_elements.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

std::string shell_cylinder_yaml(double radius_mm, double length_mm, double spacing_mm, double thickness_mm = 2,
                                double young_kpa = 20, const std::string& extra = "") {
  return "name: shell_cyl\ngravity_m_s2: [0, 0, 0]\nmaterials:\n"
         "  wall: {model: shell, thickness_mm: " + std::to_string(thickness_mm) + ", young_kpa: " +
         std::to_string(young_kpa) + ", poisson: 0.45, damping_1_s: 30" + extra +
         "}\ncomponents:\n  - {name: tube, material: wall, fill: surface, spacing_mm: " + std::to_string(spacing_mm) +
         ", cylinder: {base_mm: [0, 0, 0], radius_mm: " + std::to_string(radius_mm) + ", length_mm: " +
         std::to_string(length_mm) + "}}\n";
}

std::vector<Vec3> shell_forces(const Model& m, State& s) {
  for (auto& f : s.f) f.setZero();
  add_shell_elastic_forces(m, s);
  return s.f;
}

TEST(ShellElasticForce, FourAndEightWidePassesEqualTheScalarOnesBitForBit) {
  // blocks of four (or eight, on AVX-512) triangles / hinges run as vectors, single ones the
  // scalar code: every range gives the per-element sums bit for bit, at either width and through
  // the dispatching entry points. Large strains and bends (both atan2 branches), and one
  // collapsed triangle (its block takes the scalar path).
  auto m = test::compile_text(shell_cylinder_yaml(12, 40, 5));
  const ShellElements& sh = m->shells;
  ASSERT_GT(sh.triangle_count(), 16);
  State s = make_state(*m);
  std::mt19937 rng(3);
  std::normal_distribution<double> N(0.0, 1.2e-3);  // 1.2 mm jitter on a 5 mm spacing
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
  const int* v = &sh.tri[3 * 5];
  // triangle 5 collapsed to within 1 nm of an edge (its hinges stay finite)
  const Vec3 e = s.x[v[1]] - s.x[v[0]];
  s.x[v[2]] = s.x[v[0]] + 0.5 * e + 1e-9 * e.unitOrthogonal();
  const int n = m->particle_count(), nt = sh.triangle_count(), nh = sh.hinge_count();
  int wide_bends = 0;
  for (int h = 0; h < nh; ++h) {
    const int* w = &sh.hinge[4 * h];
    const double d = std::remainder(hinge_angle(s.x[w[0]], s.x[w[1]], s.x[w[2]], s.x[w[3]]) - sh.theta0[h], 2 * M_PI);
    wide_bends += std::abs(d) > 0.245;  // beyond atan2_small's 14 degrees: std::atan2
  }
  EXPECT_GT(wide_bends, 0);
  typedef void (*Pass)(const ShellElements&, const Vec3*, int, int, Vec3*);
  struct Width { const char* name; Pass membranes, hinges; };
  std::vector<Width> widths = {{"dispatched", add_shell_membrane_forces, add_shell_hinge_forces},
                               {"four", shell_membrane_forces4, shell_hinge_forces4}};
  if (tet_element_forces8_available()) widths.push_back({"eight", shell_membrane_forces8, shell_hinge_forces8});
  for (const Width& w : widths)
  for (const auto& [begin, end] : {std::pair{0, 1 << 30}, {1, 1 << 30}, {3, 11}, {2, 19}}) {
    std::vector<Vec3> wide(n, Vec3::Zero()), one(n, Vec3::Zero());
    w.membranes(sh, s.x.data(), begin, std::min(end, nt), wide.data());
    w.hinges(sh, s.x.data(), begin, std::min(end, nh), wide.data());
    for (int t = begin; t < std::min(end, nt); ++t) add_shell_membrane_forces(sh, s.x.data(), t, t + 1, one.data());
    for (int h = begin; h < std::min(end, nh); ++h) add_shell_hinge_forces(sh, s.x.data(), h, h + 1, one.data());
    int differing = 0;
    double largest = 0.0;
    for (int q = 0; q < n; ++q) {
      largest = std::max(largest, one[q].norm());
      EXPECT_TRUE(one[q].allFinite()) << "particle " << q;
      for (int a = 0; a < 3; ++a) differing += wide[q][a] != one[q][a];
    }
    EXPECT_EQ(differing, 0) << w.name << " lanes, range [" << begin << ", " << end << ")";
    EXPECT_GT(largest, 0.0);
  }
}

TEST(ShellElements, EveryFaceIsATriangleAndEveryInteriorEdgeAHinge) {
  auto m = test::compile_text(shell_cylinder_yaml(12, 40, 5));
  const Surface& surf = m->surfaces[0];
  EXPECT_EQ(m->shells.triangle_count(), static_cast<int>(surf.faces.size()));
  EXPECT_EQ(2 * m->shells.hinge_count(), 3 * m->shells.triangle_count()) << "a closed surface: every edge has two faces";
  for (int p = 0; p < m->particle_count(); ++p) EXPECT_EQ(m->shape_memory[p], 0) << "the elements carry the stiffness";
  EXPECT_FALSE(m->any_shape_memory);
  // the mass is the wall's: density x area x thickness
  double area = 0.0, mass = 0.0;
  for (const auto& f : surf.faces)
    area += 0.5 * (m->rest_pos[f[1]] - m->rest_pos[f[0]]).cross(m->rest_pos[f[2]] - m->rest_pos[f[0]]).norm();
  for (double w : m->mass) mass += w;
  EXPECT_NEAR(mass, 1000.0 * area * 2e-3, 1e-9 * mass);
}

TEST(ShellElements, HingeAngleIsSignedAndItsGradientExact) {
  const Vec3 x0(0, 0, 0), x1(1, 0, 0), x2(0.5, 1, 0), x3(0.5, -1, 0);
  EXPECT_NEAR(hinge_angle(x0, x1, x2, x3), 0.0, 1e-15);
  // lifting both opposite vertices folds the faces the same way: twice one vertex's angle
  const double one = hinge_angle(x0, x1, x2 + Vec3(0, 0, 0.1), x3);
  EXPECT_NEAR(hinge_angle(x0, x1, x2 + Vec3(0, 0, 0.1), x3 + Vec3(0, 0, 0.1)), 2.0 * one, 1e-12);
  EXPECT_NEAR(std::abs(one), std::atan(0.1), 1e-12);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-0.3, 0.3);
  Vec3 x[4] = {x0, x1, x2, x3};
  for (Vec3& v : x) v += Vec3(U(rng), U(rng), U(rng));
  Vec3 g[4];
  hinge_angle(x[0], x[1], x[2], x[3], g);
  for (int i = 0; i < 4; ++i)
    for (int a = 0; a < 3; ++a) {
      Vec3 xp[4] = {x[0], x[1], x[2], x[3]}, xm[4] = {x[0], x[1], x[2], x[3]};
      xp[i][a] += 1e-7;
      xm[i][a] -= 1e-7;
      const double fd = (hinge_angle(xp[0], xp[1], xp[2], xp[3]) - hinge_angle(xm[0], xm[1], xm[2], xm[3])) / 2e-7;
      EXPECT_NEAR(g[i][a], fd, 1e-6) << "vertex " << i << " axis " << a;
    }
}

TEST(ShellElasticForce, IsTheGradientOfTheEnergyAndConservesMomentum) {
  auto m = test::compile_text(shell_cylinder_yaml(12, 30, 5));
  State s = make_state(*m);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  Mat3 F;
  F << 1.15, 0.1, 0.0, -0.05, 0.9, 0.1, 0.0, 0.2, 1.05;
  std::mt19937 rng(7);
  std::normal_distribution<double> N(0.0, 1e-3);
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = R * F * m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
  const std::vector<Vec3> force = shell_forces(*m, s);
  const auto [worst, scale] = test::gradient_mismatch(s, force, 1, [&](State& st) { return shell_elastic_energy(*m, st); });
  ASSERT_GT(scale, 0.0);
  EXPECT_LE(worst, 1e-5 * scale);
  Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
  for (int p = 0; p < m->particle_count(); ++p) { sum += force[p]; torque += s.x[p].cross(force[p]); }
  EXPECT_LE(sum.norm(), 1e-10 * scale);
  EXPECT_LE(torque.norm(), 1e-10 * scale * 0.05);
}

TEST(ShellElasticForce, ZeroAtRestAndForRigidMotions) {
  auto m = test::compile_text(shell_cylinder_yaml(12, 30, 5));
  State s = make_state(*m);
  auto largest = [&] {
    double f = 0;
    for (const Vec3& v : shell_forces(*m, s)) f = std::max(f, v.norm());
    return f;
  };
  const double scale = 20e3 * 2e-3 * 1e-3;  // E t x 1 mm misfit / 1 m: a force scale [N]
  EXPECT_LE(largest(), 1e-12 * scale);
  const Mat3 R = Eigen::AngleAxisd(2.5, Vec3(0.3, -1, 0.2).normalized()).toRotationMatrix();
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = R * m->rest_pos[p] + Vec3(0.05, 0.1, -0.2);
  EXPECT_LE(largest(), 1e-9 * scale);
  EXPECT_LE(shell_elastic_energy(*m, s), 1e-18);
}

// A uniform dilation x -> (1 + e) x strains every face equibiaxially and leaves every dihedral
// angle as it was: plate theory's energy is E t A e^2 / (1 - nu) (plane stress), exactly.
TEST(ShellElasticForce, EquibiaxialStrainHasThePlateEnergy) {
  auto m = test::compile_text(shell_cylinder_yaml(12, 30, 5, 2.0, 20.0));
  State s = make_state(*m);
  const double e = 1e-3;
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = (1.0 + e) * m->rest_pos[p];
  double area = 0.0;
  for (const auto& f : m->surfaces[0].faces)
    area += 0.5 * (m->rest_pos[f[1]] - m->rest_pos[f[0]]).cross(m->rest_pos[f[2]] - m->rest_pos[f[0]]).norm();
  const double expected = 20e3 * 2e-3 * area * e * e / (1.0 - 0.45);
  EXPECT_NEAR(shell_elastic_energy(*m, s), expected, 1e-9 * expected);
}

// A closed cylinder (R = 15 mm, L = 105 mm, t = 1 mm) under internal pressure p, relaxed to rest:
// away from the caps the radius grows by the thin-shell value p R^2 (1 - nu/2) / (E t) (hoop stress
// p R / t, axial p R / 2t, whatever shape the caps take). Spacing 5 mm: about 19 faces around.
TEST(ShellElasticForce, PressurisedCylinderMatchesThinShellTheory) {
  const double R = 15e-3, L = 105e-3, t = 1e-3, E = 20e3, nu = 0.45, p = 20.0;  // [m, m, m, Pa, -, Pa]
  auto m = test::compile_text(shell_cylinder_yaml(R * 1e3, L * 1e3, 5, t * 1e3, E * 1e-3));
  State s = make_state(*m);
  const int n = m->particle_count();
  const auto& faces = m->surfaces[0].faces;
  std::vector<Vec3> v(n, Vec3::Zero());
  const double h = 0.5 * m->stable_dt_estimate, keep = 0.98;  // dynamic relaxation [s], [-]
  auto mid_growth = [&] {
    double sum = 0.0;
    int count = 0;
    for (int q = 0; q < n; ++q) {
      const Vec3 r = m->rest_pos[q];
      if (std::abs(r.z() - 0.5 * L) > 0.15 * L || std::abs(Vec3(r.x(), r.y(), 0).norm() - R) > 1e-6) continue;
      sum += Vec3(s.x[q].x(), s.x[q].y(), 0).norm() - R;
      ++count;
    }
    EXPECT_GT(count, 10);
    return sum / count;
  };
  double last = 0.0;
  for (int round = 0; round < 40; ++round) {  // until the mid-length growth settles
    for (int it = 0; it < 500; ++it) {
      for (auto& f : s.f) f.setZero();
      add_shell_elastic_forces(*m, s);
      for (const auto& f : faces) {  // pressure: p x area vector / 3 on each vertex
        const Vec3 an = 0.5 * (s.x[f[1]] - s.x[f[0]]).cross(s.x[f[2]] - s.x[f[0]]);
        for (int i : f) s.f[i] += p * an / 3.0;
      }
      for (int q = 0; q < n; ++q) {
        v[q] = keep * (v[q] + h * m->inv_mass[q] * s.f[q]);
        s.x[q] += h * v[q];
      }
    }
    const double now = mid_growth();
    if (round > 2 && std::abs(now - last) < 1e-3 * std::abs(now)) break;
    last = now;
  }
  const double expected = p * R * R * (1.0 - nu / 2.0) / (E * t);  // [m]
  const double dr = mid_growth();
  EXPECT_NEAR(dr, expected, 0.05 * expected) << "mid-length radial growth " << dr * 1e3 << " mm, thin shell "
                                             << expected * 1e3 << " mm";
}

TEST(ShellModel, RejectsAVolumetricComponentAndAMissingThickness) {
  EXPECT_THROW(test::compile_text("name: x\nmaterials: {w: {model: shell, thickness_mm: 2, young_kpa: 10}}\n"
                                  "components:\n  - {name: c, material: w, spacing_mm: 5, box: {min_mm: [0,0,0], max_mm: [20,20,20]}}\n"),
               InputError);
  EXPECT_THROW(test::compile_text("name: x\nmaterials: {w: {model: shell, young_kpa: 10}}\n"
                                  "components:\n  - {name: c, material: w, spacing_mm: 5, fill: surface, box: {min_mm: [0,0,0], max_mm: [20,20,20]}}\n"),
               InputError);
  EXPECT_THROW(test::compile_text("name: x\nmaterials: {w: {thickness_mm: 2, young_kpa: 10}}\n"
                                  "components:\n  - {name: c, material: w, spacing_mm: 5, fill: surface, box: {min_mm: [0,0,0], max_mm: [20,20,20]}}\n"),
               InputError);
}

}  // namespace
}  // namespace ps
