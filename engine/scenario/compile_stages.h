// The stages of compile_scenario (compile.cpp), each in a file named after it, and what they hand
// each other besides the Model they fill. Internal to engine/scenario: code outside calls
// compile_scenario. Every stage throws InputError (names file:line and key) or CompileError
// (names the particle or face) as compile_scenario documents.
#pragma once
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/model/model.h"
#include "engine/model/shell_elements.h"
#include "engine/model/strain_clusters.h"
#include "engine/model/tet_elements.h"
#include "engine/spec/scenario_spec.h"

namespace ps {

// Per-particle and per-component results one stage leaves for a later one.
struct CompileWork {
  std::vector<std::vector<int>> nbrs;                     // [particle] neighbours (global indices):
                                                          // the component's own, then links
  std::vector<std::vector<std::array<int, 3>>> faces_of;  // [component] closed surface (global indices)
  std::vector<double> excluded_volume;                    // [component] volume of the organs inside [m^3]
  std::vector<StrainParticle> strain;                     // [particle] strain-model material (mu = 0: none)
  std::vector<TetParticle> tet;                           // [particle] tet-model material (mu = 0: none)
  std::vector<ShellParticle> shell;                       // [particle] shell-model material (mu = 0: none)
  std::array<bool, kMaterialModelCount> uses_model{};     // [MaterialModel] some component uses it
  std::vector<std::string> warnings, notes;               // for CompileReport and Model::compile_warnings
};

// In the order compile_scenario runs them (what each reads from earlier stages):
// particles of every component, contiguous per component: rest_pos, component_of, on_surface,
// components (with their roles); work.nbrs, faces_of, excluded_volume (compile_particles.cpp)
void compile_particles(const ScenarioSpec& spec, Model& m, CompileWork& work);
// mass, k_e, k_c, k_f, damping; work.strain, tet, shell, uses_model (each material model's moduli,
// material_models.h); then overrides: (faces_of, excluded_volume) (compile_material.cpp)
void compile_material(const ScenarioSpec& spec, Model& m, CompileWork& work);
// inv_mass, shape_memory, locked_axes; rigid_bodies (mass) (compile_rigid_bodies.cpp)
void compile_rigid_bodies(const ScenarioSpec& spec, Model& m);
// links across components (rigid bodies, inv_mass; work.nbrs), then nbr / nbr_start (shape_memory)
// (compile_neighbours.cpp)
void compile_neighbours(const ScenarioSpec& spec, Model& m, CompileWork& work);
// fixed, imposed, half_spaces, applied_forces; locked_axes (compile_constraints.cpp)
void compile_constraints(const ScenarioSpec& spec, Model& m);
// surfaces with rest volumes (work.faces_of) (compile_surfaces.cpp)
void compile_surfaces(const ScenarioSpec& spec, Model& m, const CompileWork& work);
// each used material model's elements: strain clusters, tet and shell elements (surfaces,
// work.strain, tet, shell); any_shape_memory (compile_elements.cpp)
void compile_elements(const ScenarioSpec& spec, Model& m, CompileWork& work);
// fibre_pairs of active components (nbr) (compile_fibres.cpp)
void compile_fibres(Model& m);
// stable_dt_estimate, substeps; multirate order of the tets; mass scaling (every force)
// (compile_time_step.cpp)
void compile_time_step(const ScenarioSpec& spec, Model& m, CompileWork& work);
// sleep: which particles may sleep and the thresholds (tets, tet_pressure, surfaces, constraints)
// (compile_sleep.cpp)
void compile_sleep(const ScenarioSpec& spec, Model& m, CompileWork& work);
// urethra: the gland's centre line from urethra.csv beside its mesh, placed like the mesh
// (components' roles) (compile_urethra.cpp)
void compile_urethra(const ScenarioSpec& spec, Model& m);

inline const MaterialSpec& find_material(const ScenarioSpec& spec, const std::string& name) {
  for (const auto& m : spec.materials)
    if (m.name == name) return m;
  throw std::logic_error("material checked by the parser");
}

}  // namespace ps
