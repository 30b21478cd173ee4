// The material models (MaterialSpec::model), one descriptor each: what the material and elements
// stages of compile_scenario build for it, which force stage of the substep evaluates it, and
// what the time-step stage and diagnostics need of it (its force at a state, its per-particle
// stiffness proxy, its energy). One file per model (material_paper.cpp, material_strain.cpp,
// material_tet.cpp, material_shell.cpp); material_models.cpp lists them. The substep itself does
// not go through the descriptors: Simulation::step dispatches its stages with one switch
// (engine/step/simulation.cpp), and `stage` names the entry a model's force takes there.
// Adding a model: docs/architecture.md "Material models".
#pragma once
#include <span>
#include <string>
#include <vector>

#include "engine/model/material.h"
#include "engine/model/model.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/compile_stages.h"
#include "engine/spec/scenario_spec.h"
#include "engine/state/state.h"
#include "engine/step/simulation.h"

namespace ps {

// What the material stage gives every particle of one component: the shape-memory stiffness and
// the moduli of the element models (mu = 0: the particle is not in that model).
struct ParticleMaterial {
  double k_e = 0.0;  // [N/m]
  StrainParticle strain;
  TetParticle tet;
  ShellParticle shell;
};

// One component of a material, as the material stage sees it.
struct ComponentMaterialInput {
  const ScenarioSpec& spec;
  const MaterialSpec& mat;
  const ComponentSpec& cs;
  const Component& comp;
  double volume = 0.0;  // the component's material volume (organs inside left out) [m^3]
};

class ModelHasher;  // engine/scenario/model_hash.h

struct MaterialModelDesc {
  MaterialModel model;
  const char* name;  // its `model:` value in a scenario file
  Stage stage;       // the force stage that evaluates it in a substep

  // Material stage. check (may be null): refuse a component the model cannot build (names the
  // material's line and key); moduli: the per-particle values of one component of the material
  // (k_e before a raw k_e_n_m, which the stage applies on top), with any warning it raises;
  // override_young: an `overrides:` region's young_kpa on particle p of that material.
  void (*check)(const ComponentMaterialInput& in);
  void (*moduli)(const ComponentMaterialInput& in, ParticleMaterial& out, std::vector<std::string>& warnings);
  void (*override_young)(double young_pa, double spacing_m, int p, Model& m, CompileWork& work);
  // Elements stage (may be null): the model's elements from the surfaces and the moduli
  void (*build)(const ScenarioSpec& spec, Model& m, CompileWork& work);

  // The compiled model holds this term (its stage is in Simulation's pipeline).
  bool (*present)(const Model& m);
  // Adds the term's force at s.x to s.f (the stable-step estimate; tet pass as in TetPass: the
  // other terms add nothing for TetPass::SlowOnly).
  void (*add_forces)(const Model& m, State& s, TetPass pass);
  // Adds the term's per-particle stiffness proxy to d [N/m] (stiffness_proxy, compile.h).
  void (*add_stiffness)(const Model& m, bool fast_only, ProxyForm form, std::vector<double>& d);
  // The energy whose negative gradient the term's force is, at s [J] (tests, diagnostics).
  double (*energy)(const Model& m, const State& s);
  // Feeds the model's elements and their materials to the compiled model's hash (model_hash.h);
  // null when it has none beyond the per-particle arrays every model shares.
  void (*hash)(const Model& m, ModelHasher& h);
};

extern const MaterialModelDesc kPaperMaterial;
extern const MaterialModelDesc kStrainMaterial;
extern const MaterialModelDesc kTetMaterial;
extern const MaterialModelDesc kShellMaterial;

// Every model, in MaterialModel order (the order of their force stages: forces and stiffness are
// summed in it, which fixes the bits of the estimates).
std::span<const MaterialModelDesc* const> material_models();
const MaterialModelDesc& material_model(MaterialModel model);
// The model whose `model:` name this is; null when none.
const MaterialModelDesc* find_material_model(const std::string& name);
// Sum of every present term's energy at s [J] (elastic energy of the tissue; tests, diagnostics).
double elastic_energy(const Model& m, const State& s);

}  // namespace ps

namespace ps {

// The local Poisson ratio of the strain, tet and shell models: the file's, or the default of an
// incompressible or a compressible material.
inline double local_poisson(const MaterialSpec& mat) {
  return mat.poisson ? *mat.poisson : mat.incompressible ? kStrainPoissonIncompressible : kStrainPoissonDefault;
}

}  // namespace ps
