#include "engine/step/simulation.h"

#include "engine/step/stages.h"

namespace ps {

const char* stage_name(Stage s) {
  switch (s) {
    case Stage::ImposedDisplacement: return "imposed_displacement";
    case Stage::ExternalForces: return "external_forces";
    case Stage::ShapeMemory: return "shape_memory";
    case Stage::StrainMemory: return "strain_memory";
    case Stage::TetElastic: return "tet_elastic";
    case Stage::ActiveFibres: return "active_fibres";
    case Stage::ToolBoundary: return "tool_boundary";
    case Stage::ToolForces: return "tool_forces";
    case Stage::RigidForces: return "rigid_forces";
    case Stage::Integrate: return "integrate";
    case Stage::RigidIntegrate: return "rigid_integrate";
    case Stage::LocalConstraints: return "local_constraints";
    case Stage::ToolConstraints: return "tool_constraints";
    case Stage::Volume: return "volume";
    case Stage::AdjustVelocity: return "adjust_velocity";
    case Stage::Check: return "check";
    case Stage::ToolAfter: return "tool_after";
  }
  return "?";
}

Simulation::Simulation(std::shared_ptr<const Model> model)
    : model_(std::move(model)), state_(make_state(*model_)) {
  build_pipeline();
}

void Simulation::add_tool(std::unique_ptr<Tool> tool) {
  tools_.push_back(std::move(tool));
  build_pipeline();
}

void Simulation::build_pipeline() {
  const Model& m = *model_;
  pipeline_.clear();
  const bool tools = !tools_.empty();
  const bool rigid = !m.rigid_bodies.empty();
  bool volume = false;
  for (const Surface& s : m.surfaces) volume |= s.volume_constrained;
  // Algorithm 1: boundary conditions -> forces -> integrate -> constraints -> velocity adjust
  if (!m.imposed.empty()) pipeline_.push_back(Stage::ImposedDisplacement);
  if (tools) pipeline_.push_back(Stage::ToolBoundary);
  pipeline_.push_back(Stage::ExternalForces);
  if (m.any_shape_memory) pipeline_.push_back(Stage::ShapeMemory);
  if (m.strain.count() > 0) pipeline_.push_back(Stage::StrainMemory);
  if (m.tets.count() > 0) pipeline_.push_back(Stage::TetElastic);
  if (!m.fibre_pairs.empty()) pipeline_.push_back(Stage::ActiveFibres);
  if (tools) pipeline_.push_back(Stage::ToolForces);
  if (rigid) pipeline_.push_back(Stage::RigidForces);
  pipeline_.push_back(Stage::Integrate);
  if (rigid) pipeline_.push_back(Stage::RigidIntegrate);
  if (!m.fixed.empty() || !m.imposed.empty() || !m.half_spaces.empty())
    pipeline_.push_back(Stage::LocalConstraints);
  if (tools) pipeline_.push_back(Stage::ToolConstraints);
  if (volume) pipeline_.push_back(Stage::Volume);
  pipeline_.push_back(Stage::AdjustVelocity);
  pipeline_.push_back(Stage::Check);
  if (tools) pipeline_.push_back(Stage::ToolAfter);
}

bool Simulation::step(double dt) {
  const Model& m = *model_;
  State& s = state_;
  if (s.fault.kind != StepFault::None) return false;
  const double t_end = s.time + dt;  // constraints at the end of the step use its end time
  for (Stage st : pipeline_) {
    switch (st) {
      case Stage::ImposedDisplacement: apply_imposed_displacements(m, s, s.time); break;
      case Stage::ToolBoundary: for (auto& t : tools_) t->boundary_conditions(m, s, dt); break;
      case Stage::ExternalForces: clear_and_add_external_forces(m, s, s.time); break;
      case Stage::ShapeMemory: add_shape_memory_forces(m, s); break;
      case Stage::StrainMemory: add_strain_memory_forces(m, s); break;
      case Stage::TetElastic: add_tet_elastic_forces(m, s); break;
      case Stage::ActiveFibres: add_active_forces(m, s); break;
      case Stage::ToolForces: for (auto& t : tools_) t->forces(m, s, dt); break;
      case Stage::RigidForces: gather_rigid_forces(m, s); break;
      case Stage::Integrate: integrate(m, s, dt); break;
      case Stage::RigidIntegrate: integrate_rigid_bodies(m, s, dt); break;
      case Stage::LocalConstraints: apply_local_constraints(m, s, t_end); break;
      case Stage::ToolConstraints: for (auto& t : tools_) t->constraints(m, s, dt); break;
      case Stage::Volume:
        if (!project_volumes(m, s)) return false;
        break;
      case Stage::AdjustVelocity: adjust_velocities(s, dt); break;
      case Stage::Check:
        s.time = t_end;
        ++s.step;
        if (!check_state(m, s)) return false;
        break;
      case Stage::ToolAfter: for (auto& t : tools_) t->after_step(m, s, dt); break;
    }
  }
  return true;
}

bool Simulation::tick() {
  const Model& m = *model_;
  const double h = m.dt / m.substeps;
  for (int i = 0; i < m.substeps; ++i)
    if (!step(h)) return false;
  return true;
}

}  // namespace ps
