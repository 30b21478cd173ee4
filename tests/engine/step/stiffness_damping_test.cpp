// Rayleigh stiffness damping (solver.stiffness_damping_s, Model::stiffness_damping = beta;
// engine/step/stiffness_damping.cpp): the elastic stages see x + beta v. Checked against the
// linear theory it stands for: a mode of frequency omega decays at the ratio zeta = beta omega / 2,
// a rigid translation is not damped, and the stable-step estimate is the damped central-difference
// limit (2 / omega)(sqrt(1 + zeta^2) - zeta).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <memory>

#include "engine/scenario/compile.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

// A small tet block (3 x 3 x 3 particles), bottom layer fixed unless `free`, no gravity, no mass
// damping: its motion is the elastic forces' alone.
std::string block_yaml(double beta_s, bool free = false) {
  std::string s = "name: damped_block\nsolver: {stiffness_damping_s: " + std::to_string(beta_s) +
                  "}\ntime: {dt_ms: 0.1, substeps: 1, duration_s: 1}\ngravity_m_s2: [0, 0, 0]\nmaterials:\n"
                  "  soft: {model: tet, young_kpa: 10, density_kg_m3: 1000, damping_1_s: 0}\ncomponents:\n"
                  "  - {name: b, material: soft, spacing_mm: 10, box: {min_mm: [0, 0, 0], max_mm: [20, 20, 20]}}\n";
  if (!free) s += "constraints:\n  - fix: {component: b, region: {box: {min_mm: [-1, -1, -1], max_mm: [100, 100, 0.5]}}}\n";
  return s;
}

TEST(StiffnessDamping, StableStepIsTheDampedCentralDifferenceLimit) {
  auto plain = test::compile_text(block_yaml(0.0));
  auto damped = test::compile_text(block_yaml(1e-4));
  EXPECT_EQ(damped->stiffness_damping, 1e-4);
  // the same power iteration (fixed seed) finds the same omega; only the limit's form differs
  const double omega = 2.0 / plain->stable_dt_estimate;     // [rad/s]
  const double zeta = 0.5 * 1e-4 * omega;                   // [-]
  const double expected = 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
  EXPECT_NEAR(damped->stable_dt_estimate, expected, 1e-9 * expected);
  EXPECT_LT(damped->stable_dt_estimate, plain->stable_dt_estimate * (1.0 - 0.5 * zeta));
}

// The block's stiffest mode, from central differences of the elastic force at rest:
// K u = omega^2 M u over the free coordinates.
struct Mode {
  std::vector<int> dof;  // 3 p + a of each free coordinate
  Eigen::MatrixXd K;     // stiffness over dof [N/m]
  Eigen::VectorXd mass;  // [kg] per dof
  Eigen::VectorXd u;     // mode shape, M-normalised (u^T M u = 1)
  double omega = 0.0;    // [rad/s]
};

Mode stiffest_mode(const Model& m) {
  Mode md;
  std::vector<uint8_t> fixed(m.particle_count(), 0);
  for (const FixedParticle& f : m.fixed) fixed[f.particle] = 1;
  for (int p = 0; p < m.particle_count(); ++p)
    if (!fixed[p] && m.inv_mass[p] > 0.0)
      for (int a = 0; a < 3; ++a) md.dof.push_back(3 * p + a);
  const int n = static_cast<int>(md.dof.size());
  md.K.resize(n, n);
  md.mass.resize(n);
  State s = make_state(m);
  const double h = 1e-7;  // [m]
  for (int j = 0; j < n; ++j) {
    const int p = md.dof[j] / 3, a = md.dof[j] % 3;
    md.mass[j] = m.mass[p];
    Eigen::VectorXd fp(n), fm(n);
    for (int sign : {1, -1}) {
      s.x = m.rest_pos;
      s.x[p][a] += sign * h;
      for (Vec3& f : s.f) f.setZero();
      add_tet_elastic_forces(m, s);
      Eigen::VectorXd& out = sign > 0 ? fp : fm;
      for (int i = 0; i < n; ++i) out[i] = s.f[md.dof[i] / 3][md.dof[i] % 3];
    }
    md.K.col(j) = -(fp - fm) / (2.0 * h);
  }
  md.K = 0.5 * (md.K + md.K.transpose());
  const Eigen::VectorXd isq = md.mass.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd A = isq.asDiagonal() * md.K * isq.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  md.omega = std::sqrt(es.eigenvalues()[n - 1]);
  md.u = isq.asDiagonal() * es.eigenvectors().col(n - 1);
  return md;
}

// kinetic + elastic energy of the linearised block [J]
double energy(const Model& m, const State& s, const Mode& md) {
  const int n = static_cast<int>(md.dof.size());
  Eigen::VectorXd u(n), v(n);
  for (int i = 0; i < n; ++i) {
    const int p = md.dof[i] / 3, a = md.dof[i] % 3;
    u[i] = s.x[p][a] - m.rest_pos[p][a];
    v[i] = s.v[p][a];
  }
  return 0.5 * v.dot(md.mass.asDiagonal() * v) + 0.5 * u.dot(md.K * u);
}

// Five periods of the stiffest mode, started from rest positions with the mode's velocity
// (small: linear), at 100 substeps per period; returns E(5 T) / E(0).
double energy_left_after_five_periods(const Model& compiled, double beta, const Mode& md) {
  auto m = std::make_shared<Model>(compiled);
  const double period = 2.0 * M_PI / md.omega;  // [s]
  m->dt = period / 100.0;
  m->substeps = 1;
  m->stiffness_damping = beta;
  Simulation sim(m);
  State& s = sim.state();
  if (beta > 0.0 && s.x_shift.empty()) ADD_FAILURE() << "no damping scratch";
  const double v0 = 1e-4 / std::sqrt(md.u.dot(md.mass.asDiagonal() * md.u) / md.mass.sum());  // ~0.1 mm/s [m/s]
  for (size_t i = 0; i < md.dof.size(); ++i) s.v[md.dof[i] / 3][md.dof[i] % 3] = v0 * md.u[i];
  const double e0 = energy(*m, s, md);
  for (int k = 0; k < 500; ++k) EXPECT_TRUE(sim.tick()) << s.fault.describe(*m);
  return energy(*m, s, md) / e0;
}

TEST(StiffnessDamping, DampsTheStiffestModeAtZetaEqualBetaOmegaOverTwo) {
  auto m = test::compile_text(block_yaml(0.0));
  const Mode md = stiffest_mode(*m);
  ASSERT_GT(md.omega, 100.0);
  // undamped: the symplectic step keeps the mode's energy
  const double kept = energy_left_after_five_periods(*m, 0.0, md);
  EXPECT_NEAR(kept, 1.0, 0.01);
  // zeta = 0.02: E(t) = E0 exp(-2 zeta omega t), 0.285 after five periods
  const double zeta = 0.02, beta = 2.0 * zeta / md.omega;  // [-], [s]
  const double left = energy_left_after_five_periods(*m, beta, md);
  const double measured_zeta = -std::log(left) / (2.0 * md.omega * 5.0 * 2.0 * M_PI / md.omega);
  EXPECT_NEAR(measured_zeta, zeta, 0.05 * zeta) << "energy left " << left;
}

TEST(StiffnessDamping, LeavesARigidTranslationAlone) {
  // a free block moving as a whole: x + beta v is the same translation for every particle, so no
  // elastic force appears and the velocity stays what it was (mass-proportional damping would
  // slow it)
  auto m = test::compile_text(block_yaml(1e-3, true));
  Simulation sim(m);
  const Vec3 v0(0.02, -0.01, 0.03);  // [m/s]
  for (Vec3& v : sim.state().v) v = v0;
  for (int k = 0; k < 200; ++k) ASSERT_TRUE(sim.tick());
  double worst = 0.0;
  for (const Vec3& v : sim.state().v) worst = std::max(worst, (v - v0).norm());
  EXPECT_LT(worst, 1e-9 * v0.norm());
  // and the positions are the true ones between ticks (the shift swapped back)
  const double t = sim.state().time;
  for (int p = 0; p < m->particle_count(); ++p)
    EXPECT_LT((sim.state().x[p] - (m->rest_pos[p] + t * v0)).norm(), 1e-12) << "particle " << p;
}

TEST(StiffnessDamping, RefusesABetaOutOfRange) {
  test::expect_refused_with_field(block_yaml(0.01), "solver.stiffness_damping_s");
  test::expect_refused_with_field(block_yaml(-1e-5), "solver.stiffness_damping_s");
}

}  // namespace
}  // namespace ps
