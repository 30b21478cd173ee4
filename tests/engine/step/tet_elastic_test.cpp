// Tet-model force (engine/step/tet_elastic.cpp): the exact gradient of its energy, zero at rest
// and for rigid motions, momentum conserving, the patch test (a uniform deformation is in
// equilibrium inside the body), Hooke's energy density for a small strain, finite for inverted
// and collapsed bodies, and no allocation in the step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "engine/model/material.h"
#include "engine/model/tet_elements.h"
#include "engine/step/simulation.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

std::string tet_cube_yaml(double side = 40, double h = 10, const std::string& extra = "") {
  const std::string s = std::to_string(side);
  return "name: tet_cube\ntime: {dt_ms: 1, substeps: 1, duration_s: 1}\ngravity_m_s2: [0, 0, 0]\nmaterials:\n"
         "  gel: {young_kpa: 10, damping_1_s: 30, incompressible: true, model: tet" + extra +
         "}\ncomponents:\n  - name: cube\n    material: gel\n    spacing_mm: " + std::to_string(h) +
         "\n    box: {min_mm: [0, 0, 0], max_mm: [" + s + ", " + s + ", " + s + "]}\n";
}
// a mesh-filled cylinder: surface vertices plus an interior lattice, irregular near the surface
const char* kCylinderYaml =
    "name: tet_cyl\nmaterials: {soft: {young_kpa: 60, model: tet}}\ncomponents:\n"
    "  - {name: c, material: soft, spacing_mm: 6, cylinder: {radius_mm: 12, length_mm: 30}}\n";

std::vector<Vec3> tet_forces(const Model& m, State& s) {
  for (auto& f : s.f) f.setZero();
  add_tet_elastic_forces(m, s);
  return s.f;
}

TEST(TetElasticForce, IsTheGradientOfTheEnergyAndConservesMomentum) {
  for (const std::string& yaml : {tet_cube_yaml(30, 10), std::string(kCylinderYaml)}) {
    auto m = test::compile_text(yaml);
    ASSERT_GT(m->tets.count(), 0);
    State s = make_state(*m);
    const Mat3 R = Eigen::AngleAxisd(0.5, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    Mat3 F;
    F << 1.2, 0.1, 0.0, -0.05, 0.9, 0.1, 0.0, 0.2, 1.05;
    std::mt19937 rng(5);
    std::normal_distribution<double> N(0.0, 1e-3);
    for (int p = 0; p < m->particle_count(); ++p) s.x[p] = R * F * m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
    const std::vector<Vec3> force = tet_forces(*m, s);
    const auto [worst, scale] = test::gradient_mismatch(s, force, 3, [&](State& st) { return tet_elastic_energy(*m, st); });
    ASSERT_GT(scale, 0.0);
    EXPECT_LE(worst, 1e-6 * scale) << m->name;
    Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
    for (int p = 0; p < m->particle_count(); ++p) { sum += force[p]; torque += s.x[p].cross(force[p]); }
    EXPECT_LE(sum.norm(), 1e-10 * scale) << m->name;
    EXPECT_LE(torque.norm(), 1e-10 * scale * 0.05) << m->name;  // exact: the energy is rotation invariant
  }
}

// Particles jittered by 0.8 mm about rest (6 mm spacing: large, irregular strains), and node
// pressures from the resulting volumes plus 1 kPa on every node (also where the material's pressure
// is implicit): a state where every term of the element force is non-zero.
void jitter_with_pressure(const Model& m, unsigned seed, State& s, std::vector<double>& p) {
  const TetElements& te = m.tets;
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 0.8e-3);
  for (int q = 0; q < m.particle_count(); ++q) s.x[q] = m.rest_pos[q] + Vec3(N(rng), N(rng), N(rng));
  p.assign(te.nodes.size(), 0.0);
  add_tet_node_volumes(te, s.x.data(), nullptr, te.count(), p.data());
  tet_node_pressures(te, p.data());
  for (double& q : p) q += 1e3;
}

// The element pass runs four elements per vector (and, on a machine that has them, AVX or
// AVX-512 clones of that code, chosen at load time); each lane must do the scalar pass's
// operations in the same order, so that a replay gives the same bits on every machine. Here
// the pass over all elements at once (vector lanes) against the same elements one at a time
// (a one-element list runs the scalar tail), accumulated in the same order: equal to the bit.
TEST(TetElasticForce, VectorPassEqualsTheScalarPassBitForBit) {
  auto m = test::compile_text(kCylinderYaml);
  const TetElements& te = m->tets;
  ASSERT_GT(te.count(), 16);
  State s = make_state(*m);
  std::vector<double> p;
  jitter_with_pressure(*m, 11, s, p);
  std::vector<Vec3> all(m->particle_count(), Vec3::Zero()), one(m->particle_count(), Vec3::Zero());
  add_tet_element_forces(te, s.x.data(), p.data(), nullptr, te.count(), all.data());
  for (int t = 0; t < te.count(); ++t) add_tet_element_forces(te, s.x.data(), p.data(), &t, 1, one.data());
  int differing = 0;
  for (int q = 0; q < m->particle_count(); ++q)
    for (int a = 0; a < 3; ++a) differing += all[q][a] != one[q][a];
  EXPECT_EQ(differing, 0) << "of " << 3 * m->particle_count() << " force components";
  double largest = 0.0;
  for (const Vec3& f : all) largest = std::max(largest, f.norm());
  EXPECT_GT(largest, 0.0);
}

TEST(TetElasticForce, BlockedRangesEqualTheScalarPassBitForBit) {
  // ranges in index order read g from its blocked copy (TetElements::g4) once they reach a block
  // boundary; a range starting inside a block (the multi-rate slow group does) begins with the
  // scalar pass. Every start and end gives the per-element sums, and so does the pass without g4.
  auto m = test::compile_text(kCylinderYaml);
  const TetElements& te = m->tets;
  ASSERT_GT(te.count(), 16);
  ASSERT_GE(te.g4.size(), te.g.size());
  TetElements unpacked = te;
  unpacked.g4.clear();
  State s = make_state(*m);
  std::vector<double> p;
  jitter_with_pressure(*m, 5, s, p);
  const int n = m->particle_count(), nt = te.count();
  for (const auto& [begin, end] : {std::pair{0, nt}, {1, nt}, {2, nt - 1}, {3, nt - 2}, {5, 7}, {6, 7}, {nt - 3, nt}}) {
    std::vector<Vec3> blocked(n, Vec3::Zero()), gathered(n, Vec3::Zero()), one(n, Vec3::Zero());
    tet_element_forces(te, s.x.data(), p.data(), nullptr, begin, end, 1.0, blocked.data());
    tet_element_forces(unpacked, s.x.data(), p.data(), nullptr, begin, end, 1.0, gathered.data());
    for (int t = begin; t < end; ++t) add_tet_element_forces(te, s.x.data(), p.data(), &t, 1, one.data());
    int differing = 0;
    for (int q = 0; q < n; ++q)
      for (int a = 0; a < 3; ++a) differing += (blocked[q][a] != one[q][a]) + (gathered[q][a] != one[q][a]);
    EXPECT_EQ(differing, 0) << "elements [" << begin << ", " << end << ")";
  }
}

TEST(TetElasticForce, FourAndEightLanesEqualTheScalarPassBitForBit) {
  // the pass four elements per vector and eight per vector (AVX-512, where the CPU has it; else the
  // eight-lane entry runs the four-lane pass) against one element at a time: ranges with blocks of
  // eight, a last block of four and a scalar tail, a head inside a block, and an element list
  auto m = test::compile_text(kCylinderYaml);
  const TetElements& te = m->tets;
  ASSERT_GT(te.count(), 40);
  State s = make_state(*m);
  std::vector<double> p;
  jitter_with_pressure(*m, 17, s, p);
  const int n = m->particle_count(), nt = te.count();
  std::vector<int> list;  // every third element, ascending (a sleeping scene's evaluated ones)
  for (int t = 0; t < nt; t += 3) list.push_back(t);
  const int nl = static_cast<int>(list.size());
  struct Range { const int* list; int begin, end; };
  for (const Range& r : {Range{nullptr, 0, nt}, Range{nullptr, 0, 13}, Range{nullptr, 3, 29}, Range{nullptr, 4, 16},
                         Range{nullptr, 1, nt - 1}, Range{list.data(), 0, nl}, Range{list.data(), 2, nl - 5}}) {
    std::vector<Vec3> four(n, Vec3::Zero()), eight(n, Vec3::Zero()), one(n, Vec3::Zero());
    tet_element_forces4(te, s.x.data(), p.data(), r.list, r.begin, r.end, 0.5, four.data());
    // the AVX-512 entry only where the CPU has it (as tet_element_forces dispatches), else four lanes
    if (tet_element_forces8_available()) tet_element_forces8(te, s.x.data(), p.data(), r.list, r.begin, r.end, 0.5, eight.data());
    else tet_element_forces4(te, s.x.data(), p.data(), r.list, r.begin, r.end, 0.5, eight.data());
    for (int k = r.begin; k < r.end; ++k) {
      const int t = r.list ? r.list[k] : k;
      tet_element_forces(te, s.x.data(), p.data(), &t, 0, 1, 0.5, one.data());
    }
    int differing = 0;
    for (int q = 0; q < n; ++q)
      for (int a = 0; a < 3; ++a) differing += (four[q][a] != one[q][a]) + (eight[q][a] != one[q][a]);
    EXPECT_EQ(differing, 0) << (r.list ? "list " : "elements ") << "[" << r.begin << ", " << r.end << ")";
  }
  if (!tet_element_forces8_available()) std::printf("no AVX-512 here: the eight-lane entry ran the four-lane pass\n");
}

TEST(TetElasticForce, EdgesKeptByTheVolumePassGiveTheSameForcesBitForBit) {
  // the volume pass of a gathered range keeps each element's edges (State::tet_edges) and the force
  // pass reads them instead of the positions: the same subtractions, so the same bits, at both
  // vector widths, with heads and tails of the range outside whole blocks; a range the volumes
  // scatter keeps none and says so
  auto m = test::compile_text(kCylinderYaml);
  TetElements te = m->tets;
  const int nt = te.count(), nn = static_cast<int>(te.nodes.size()), n = m->particle_count();
  ASSERT_GT(nt, 40);
  te.fast_count = nt / 3 + 1;  // a split like the one multi-rate makes, not on a block boundary
  pack_tet_blocks(te);
  State s = make_state(*m);
  std::vector<double> p;
  jitter_with_pressure(*m, 23, s, p);
  const int nf = te.fast_count;
  for (const auto& [begin, end] : {std::pair{0, nf}, {nf, nt}, {0, nt}, {1, nt}}) {
    std::fill(s.tet_edges.begin(), s.tet_edges.end(), std::nan(""));
    std::vector<double> vol(nn, 0.0);
    const bool kept = add_tet_range_volumes(te, s.x.data(), begin, end, s.tet_quarter.data(), vol.data(), s.tet_edges.data());
    const bool gathered = !(begin == 1 && end == nt);
    EXPECT_EQ(kept, gathered) << "elements [" << begin << ", " << end << ")";
    if (!kept) continue;
    int wrong_edges = 0;
    for (int t = begin; t < end; ++t)
      for (int j = 0; j < 3; ++j)
        for (int r = 0; r < 3; ++r) {
          const double e = s.x[te.v[4 * t + j + 1]][r] - s.x[te.v[4 * t]][r];
          wrong_edges += std::memcmp(&s.tet_edges[(3 * j + r) * nt + t], &e, sizeof(double)) != 0;
        }
    EXPECT_EQ(wrong_edges, 0) << "elements [" << begin << ", " << end << ")";
    std::vector<Vec3> read4(n, Vec3::Zero()), read8(n, Vec3::Zero()), gather(n, Vec3::Zero());
    tet_element_forces4(te, s.x.data(), p.data(), nullptr, begin, end, 0.5, read4.data(), s.tet_edges.data());
    if (tet_element_forces8_available()) tet_element_forces8(te, s.x.data(), p.data(), nullptr, begin, end, 0.5, read8.data(), s.tet_edges.data());
    else tet_element_forces4(te, s.x.data(), p.data(), nullptr, begin, end, 0.5, read8.data(), s.tet_edges.data());
    tet_element_forces(te, s.x.data(), p.data(), nullptr, begin, end, 0.5, gather.data());
    int differing = 0;
    for (int q = 0; q < n; ++q)
      for (int a = 0; a < 3; ++a)
        differing += (std::memcmp(&read4[q][a], &gather[q][a], sizeof(double)) != 0) +
                     (std::memcmp(&read8[q][a], &gather[q][a], sizeof(double)) != 0);
    EXPECT_EQ(differing, 0) << "elements [" << begin << ", " << end << ")";
  }
}

TEST(TetElasticForce, GatheredNodeVolumesEqualTheScatterBitForBit) {
  // the node volumes of the fast group, the slow group and all elements are summed per node over
  // its element list in element order, four nodes side by side (TetElements::gather_elem, padded
  // with -0.0): the scatter's additions in the scatter's order, so the same bits; another range
  // falls back to the scatter. Negative zeros and exact cancellations included: the padding must
  // leave every bit, the sign of a zero too.
  auto m = test::compile_text(kCylinderYaml);
  TetElements te = m->tets;
  const int nt = te.count(), nn = static_cast<int>(te.nodes.size());
  ASSERT_GT(nt, 16);
  te.fast_count = nt / 3;  // a split like the one multi-rate makes
  pack_tet_blocks(te);
  State s = make_state(*m);
  std::mt19937 rng(7);
  std::normal_distribution<double> N(0.0, 0.8e-3);
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
  std::vector<double> q(nt + 1, -0.0);  // the last: the gather's padding
  tet_quarters(te.v.data(), s.x.data(), 0, nt, q.data());
  for (int t = 0; t < nt; ++t) {
    const int* v = &te.v[4 * t];
    const Vec3 x0 = s.x[v[0]];
    EXPECT_EQ(q[t], (s.x[v[1]] - x0).dot((s.x[v[2]] - x0).cross(s.x[v[3]] - x0)) / 24.0) << "element " << t;
  }
  const int nf = te.fast_count;
  for (const auto& [begin, end] : {std::pair{0, nf}, {nf, nt}, {0, nt}, {1, nt}}) {
    std::vector<double> gathered(nn), scattered(nn);
    // a held part first, as the step has; -0.0 where it is zero, which padding with +0.0 would turn
    // into +0.0 on a node that has no element in the range
    for (int a = 0; a < nn; ++a) gathered[a] = scattered[a] = a % 5 == 0 ? -0.0 : 1e-7 * (a % 5);
    add_tet_range_volumes(te, s.x.data(), begin, end, q.data(), gathered.data());
    std::vector<int> list;
    for (int t = begin; t < end; ++t) list.push_back(t);
    add_tet_node_volumes(te, s.x.data(), list.data(), end - begin, scattered.data());
    int differing = 0;
    for (int a = 0; a < nn; ++a) differing += std::memcmp(&gathered[a], &scattered[a], sizeof(double)) != 0;  // every bit
    EXPECT_EQ(differing, 0) << "elements [" << begin << ", " << end << ")";
  }
}

TEST(TetElasticForce, ZeroAtRestAndForRigidMotions) {
  auto m = test::compile_text(kCylinderYaml);
  State s = make_state(*m);
  const double scale = 60e3 * 6e-3 * 1e-3;  // E h x 1 mm: the force of a 1 mm misfit [N]
  auto largest = [&] {
    double f = 0;
    for (const Vec3& v : tet_forces(*m, s)) f = std::max(f, v.norm());
    return f;
  };
  EXPECT_LE(largest(), 1e-12 * scale);
  const Mat3 R = Eigen::AngleAxisd(2.0, Vec3(-1, 0.3, 0.7).normalized()).toRotationMatrix();
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = R * m->rest_pos[p] + Vec3(0.1, -0.2, 0.05);
  EXPECT_LE(largest(), 1e-9 * scale);
}

// Patch test: under a uniform deformation F every element has the same stress, so the force on
// a particle all of whose elements are inside the body is zero (the divergence of a uniform
// stress); only particles on the surface carry force. Checked on the mesh-filled cylinder,
// whose Delaunay elements near the surface are irregular.
TEST(TetElasticForce, PassesThePatchTest) {
  for (const std::string& yaml : {tet_cube_yaml(40, 10), std::string(kCylinderYaml)}) {
    auto m = test::compile_text(yaml);
    State s = make_state(*m);
    Mat3 F;
    F << 1.05, 0.02, 0.0, 0.0, 0.97, 0.01, 0.03, 0.0, 1.02;
    for (int p = 0; p < m->particle_count(); ++p) s.x[p] = F * m->rest_pos[p];
    const std::vector<Vec3> force = tet_forces(*m, s);
    double worst_inside = 0, scale = 0;
    int inside = 0;
    for (int p = 0; p < m->particle_count(); ++p) {
      scale = std::max(scale, force[p].norm());
      if (m->on_surface[p]) continue;
      ++inside;
      worst_inside = std::max(worst_inside, force[p].norm());
    }
    ASSERT_GT(inside, 0);
    ASSERT_GT(scale, 0.0);
    EXPECT_LE(worst_inside, 1e-9 * scale) << m->name;
  }
}

// A small uniform strain stores V (mu |eps|^2 + lambda/2 (tr eps)^2): the mapping is Hooke's.
TEST(TetElasticMapping, EnergyDensityOfASmallStrain) {
  auto m = test::compile_text(tet_cube_yaml(40, 10, ", poisson: 0.3"));
  const StrainModuli sm = strain_moduli(10e3, 0.3);
  double vol = 0;
  for (double v : m->tets.vol0) vol += v;
  EXPECT_NEAR(vol, 0.04 * 0.04 * 0.04, 1e-12);  // the elements tile the cube
  State s = make_state(*m);
  Mat3 eps;
  eps << 1e-4, 2e-5, 0, 2e-5, -3e-5, 1e-5, 0, 1e-5, 5e-5;
  for (int p = 0; p < m->particle_count(); ++p) s.x[p] = (Mat3::Identity() + eps) * m->rest_pos[p];
  const double w = (sm.mu * eps.squaredNorm() + 0.5 * sm.lambda * eps.trace() * eps.trace()) * vol;
  EXPECT_NEAR(tet_elastic_energy(*m, s), w, 1e-3 * w);
}

// Inverted (mirrored) and collapsed bodies give finite forces; a body crushed to 30 % of its
// height and released returns to its rest shape.
TEST(TetElasticForce, InvertedCollapsedAndCrushedBodies) {
  auto m = test::compile_text(tet_cube_yaml(30, 10));
  for (int config = 0; config < 2; ++config) {
    State s = make_state(*m);
    for (int p = 0; p < m->particle_count(); ++p) {
      s.x[p] = m->rest_pos[p];
      if (config == 0) s.x[p].z() = 0.03 - m->rest_pos[p].z();
      else s.x[p] = Vec3(0.01, 0.01, 0.01);
    }
    for (const Vec3& f : tet_forces(*m, s)) EXPECT_TRUE(f.allFinite()) << config;
    EXPECT_TRUE(std::isfinite(tet_elastic_energy(*m, s)));
  }
  auto free_cube = test::compile_text(
      "name: t\ntime: {dt_ms: 1, substeps: 1, duration_s: 1}\ngravity_m_s2: [0, 0, 0]\n"
      "materials:\n  gel: {young_kpa: 10, damping_1_s: 30, model: tet}\ncomponents:\n"
      "  - {name: b, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [30,30,30]}}\n");
  Simulation sim(free_cube);
  State& s = sim.state();
  for (int p = 0; p < free_cube->particle_count(); ++p) s.x[p].z() = 0.3 * free_cube->rest_pos[p].z();
  s.x_prev = s.x;
  const double e0 = tet_elastic_energy(*free_cube, s);
  ASSERT_GT(e0, 0.0);
  for (int i = 0; i < 3000; ++i) ASSERT_TRUE(sim.tick()) << s.fault.describe(*free_cube);
  EXPECT_LT(tet_elastic_energy(*free_cube, s), 1e-6 * e0);
}

TEST(TetElasticForce, StepDoesNotAllocateAndIsDeterministic) {
  auto m = test::compile_text(tet_cube_yaml(40, 10));
  Simulation a(m), b(m);
  for (int p = 0; p < m->particle_count(); ++p) {
    a.state().x[p] += Vec3(0, 0, 1e-3 * std::sin(37.0 * p));
    b.state().x[p] = a.state().x[p];
  }
  ASSERT_TRUE(a.tick());
  const long before = test::allocation_count();
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(a.tick());
  EXPECT_EQ(test::allocation_count() - before, 0);
  for (int i = 0; i < 21; ++i) ASSERT_TRUE(b.tick());
  for (int p = 0; p < m->particle_count(); ++p) EXPECT_EQ(a.state().x[p], b.state().x[p]);
}

// The tet model leaves the paper's shape-memory stage out; the paper model keeps it and has no elements.
TEST(TetElasticMapping, PipelineAndPaperModel) {
  auto m = test::compile_text(tet_cube_yaml());
  Simulation sim(m);
  const auto& pl = sim.pipeline();
  EXPECT_NE(std::find(pl.begin(), pl.end(), Stage::TetElastic), pl.end());
  EXPECT_EQ(std::find(pl.begin(), pl.end(), Stage::ShapeMemory), pl.end());
  auto paper = test::compile_text(test::cube_yaml());
  EXPECT_EQ(paper->tets.count(), 0);
}

TEST(TetElasticMapping, SurfaceComponentIsRefused) {
  const std::string y =
      "name: t\nmaterials:\n  gel: {young_kpa: 10, model: tet}\ncomponents:\n"
      "  - {name: skin, material: gel, spacing_mm: 10, fill: surface, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n";
  try {
    test::compile_text(y);
    FAIL() << "a tet-model membrane was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "materials.gel.model");
    EXPECT_EQ(e.line(), 3);
  }
}

}  // namespace
}  // namespace ps
