// compile_scenario: the list of stages, each in its own file (compile_stages.h says what each
// one reads and writes). The order matters and is the order the Model's fields depend on each
// other: links attach to rigid bodies (so after them), the discrete coordinates need every
// neighbour list, the strain clusters and tet elements need the surfaces, and the stable time
// step needs every force.
#include "engine/scenario/compile.h"

#include <chrono>

#include "engine/model/discrete_coordinates.h"
#include "engine/model/tet_elements.h"
#include "engine/model/tet_pressure.h"
#include "engine/scenario/compile_stages.h"
#include "engine/scenario/scene_regions.h"
#include "engine/scenario/size_estimate.h"

namespace ps {

std::shared_ptr<const Model> compile_scenario(const ScenarioSpec& spec, CompileReport* report) {
  const auto t_start = std::chrono::steady_clock::now();
  check_scenario_size(spec);  // refuses before allocating: names the spacing_mm to change
  auto model = std::make_shared<Model>();
  Model& m = *model;
  m.name = spec.name;
  m.source_file = spec.file;
  m.dt = spec.dt;
  m.substeps = spec.substeps;
  m.duration = spec.duration;
  m.leave_margin = spec.leave_margin;
  m.gravity = spec.gravity;
  m.redistribution = spec.linear_redistribution ? Redistribution::Linear : Redistribution::Gradient;
  m.max_triplets = spec.max_triplets;
  m.stiffness_damping = spec.stiffness_damping;
  CompileWork work;

  compile_particles(spec, m, work);                      // particles of every component, contiguous per component
  compile_material(spec, m, work);                       // mass, stiffness, strain/tet moduli; overrides:
  anatomy::apply_particle_tags(spec, m, work.faces_of);  // tags: and prostate_zones:
  compile_rigid_bodies(spec, m);                         // rigid components become bodies
  compile_neighbours(spec, m, work);                     // links across components; neighbour lists to CSR
  compile_constraints(spec, m);                          // fix, displace, half-space, force
  compute_discrete_coordinates(m);                       // triplets and weights of every neighbourhood
  compile_surfaces(spec, m, work);                       // one closed surface per component, rest volumes
  compile_elements(spec, m, work);                       // strain clusters, tet elements (use the surfaces)
  compile_fibres(m);                                     // active fibres
  compile_time_step(spec, m, work);                      // stable substep; multirate, mass scaling, substeps
  pack_tet_blocks(m.tets);                               // the element pass's 4-lane copy of g (final order)
  if (std::string note = build_tet_pressure(m, spec.pressure_iterations); !note.empty())
    work.notes.push_back(note);                          // implicit pressure: factor for the final substep
  compile_sleep(spec, m, work);                          // sleeping tissue: who may sleep (needs the pressure's support)
  compile_urethra(spec, m);                              // the gland's urethra centre line (roles, the mesh's placement)

  const auto& warnings = work.warnings;
  const auto& notes = work.notes;
  m.compile_warnings = warnings;
  if (report) {
    report->warnings = warnings;
    report->notes = notes;
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  }
  return model;
}

}  // namespace ps
