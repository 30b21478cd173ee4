// The material models' descriptors (engine/scenario/material_models.h): one per MaterialModel in
// stage order, found by their scenario-file names; a compiled model holds a term exactly when its
// force stage is in the substep's pipeline; each term's force (as the stable-step estimate adds
// it) is the negative gradient of the energy its descriptor gives.
#include "engine/scenario/material_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "engine/step/simulation.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

// One small scene per model: a paper cylinder, a strain cube, a tet cube, a shell tube.
std::string scene_of(MaterialModel model) {
  switch (model) {
    case MaterialModel::Paper:
      return "name: paper\ngravity_m_s2: [0, 0, 0]\nmaterials: {soft: {young_kpa: 60}}\ncomponents:\n"
             "  - {name: c, material: soft, spacing_mm: 6, cylinder: {radius_mm: 12, length_mm: 30}}\n";
    case MaterialModel::Strain:
      return "name: strain\ngravity_m_s2: [0, 0, 0]\nmaterials: {gel: {young_kpa: 10, incompressible: true, model: strain}}\n"
             "components:\n  - {name: b, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [30,30,30]}}\n";
    case MaterialModel::Tet:
      return "name: tet\ngravity_m_s2: [0, 0, 0]\nmaterials: {gel: {young_kpa: 10, incompressible: true, model: tet}}\n"
             "components:\n  - {name: b, material: gel, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [30,30,30]}}\n";
    case MaterialModel::Shell:
      return "name: shell\ngravity_m_s2: [0, 0, 0]\nmaterials: {wall: {model: shell, thickness_mm: 2, young_kpa: 20, "
             "poisson: 0.45}}\ncomponents:\n  - {name: tube, material: wall, fill: surface, spacing_mm: 5, "
             "cylinder: {base_mm: [0, 0, 0], radius_mm: 12, length_mm: 30}}\n";
  }
  return {};
}

TEST(MaterialModels, OnePerModelInStageOrderFoundByName) {
  const auto models = material_models();
  ASSERT_EQ(static_cast<int>(models.size()), kMaterialModelCount);
  for (int i = 0; i < kMaterialModelCount; ++i) {
    const MaterialModelDesc& d = *models[i];
    EXPECT_EQ(static_cast<int>(d.model), i);
    EXPECT_EQ(&material_model(d.model), &d);
    EXPECT_EQ(find_material_model(d.name), &d);
    if (i > 0) EXPECT_LT(static_cast<int>(models[i - 1]->stage), static_cast<int>(d.stage)) << d.name;
    EXPECT_TRUE(d.moduli && d.override_young && d.present && d.add_forces && d.add_stiffness && d.energy) << d.name;
  }
  EXPECT_EQ(find_material_model("fem"), nullptr);
  EXPECT_EQ(find_material_model(""), nullptr);
}

TEST(MaterialModels, ATermIsPresentExactlyWhenItsStageRuns) {
  for (const MaterialModelDesc* own : material_models()) {
    Simulation sim(test::compile_text(scene_of(own->model)));
    const auto& pl = sim.pipeline();
    EXPECT_TRUE(own->present(sim.model())) << own->name;
    for (const MaterialModelDesc* d : material_models())
      EXPECT_EQ(d->present(sim.model()), std::find(pl.begin(), pl.end(), d->stage) != pl.end())
          << own->name << " scene, " << d->name << " term";
  }
}

TEST(MaterialModels, EachTermsForceIsTheGradientOfItsEnergy) {
  for (const MaterialModelDesc* d : material_models()) {
    auto m = test::compile_text(scene_of(d->model));
    State s = make_state(*m);
    std::mt19937 rng(7);
    std::normal_distribution<double> N(0.0, 1e-3);
    for (int p = 0; p < m->particle_count(); ++p) s.x[p] = m->rest_pos[p] + Vec3(N(rng), N(rng), N(rng));
    auto force = [&](State& st) {
      for (auto& f : st.f) f.setZero();
      d->add_forces(*m, st, TetPass::All);
      return st.f;
    };
    const std::vector<Vec3> f = force(s);
    const auto [worst, scale] = test::gradient_mismatch(s, f, 3, [&](State& st) { return d->energy(*m, st); });
    ASSERT_GT(scale, 0.0) << d->name;
    EXPECT_LE(worst, 1e-5 * scale) << d->name;
    // the scene's elastic energy holds this term's (a strain scene's paper term adds its own)
    EXPECT_GT(d->energy(*m, s), 0.0) << d->name;
    EXPECT_GE(elastic_energy(*m, s), d->energy(*m, s)) << d->name;
    // the stiffness proxy: some particle carries the term
    std::vector<double> k(m->particle_count(), 0.0);
    d->add_stiffness(*m, false, ProxyForm::Diagonal, k);
    EXPECT_GT(*std::max_element(k.begin(), k.end()), 0.0) << d->name;
  }
}

}  // namespace
}  // namespace ps
