#include "engine/step/simulation.h"

#include <cstring>

#include "engine/step/stages.h"

namespace ps {

const StepContext Tool::kLoneStep{};

void CommandRefusal::set(const char* msg) {
  std::strncpy(text, msg, sizeof text - 1);
  text[sizeof text - 1] = 0;
}

const char* stage_name(Stage s) {
  switch (s) {
    case Stage::ImposedDisplacement: return "imposed_displacement";
    case Stage::ToolBoundary: return "tool_boundary";
    case Stage::ExternalForces: return "external_forces";
    case Stage::DampingShift: return "damping_shift";
    case Stage::ShapeMemory: return "shape_memory";
    case Stage::StrainMemory: return "strain_memory";
    case Stage::TetElastic: return "tet_elastic";
    case Stage::ShellElastic: return "shell_elastic";
    case Stage::DampingUnshift: return "damping_unshift";
    case Stage::ActiveFibres: return "active_fibres";
    case Stage::ToolForces: return "tool_forces";
    case Stage::RigidForces: return "rigid_forces";
    case Stage::Integrate: return "integrate";
    case Stage::RigidIntegrate: return "rigid_integrate";
    case Stage::TetPressure: return "tet_pressure";
    case Stage::LocalConstraints: return "local_constraints";
    case Stage::ToolConstraints: return "tool_constraints";
    case Stage::Volume: return "volume";
    case Stage::AdjustVelocity: return "adjust_velocity";
    case Stage::TetTickEnd: return "tet_tick_end";
    case Stage::Sleep: return "sleep";
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
  tool->ctx_ = ctx_.get();
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
  const bool damped = m.stiffness_damping > 0.0;
  if (damped) pipeline_.push_back(Stage::DampingShift);
  if (m.any_shape_memory) pipeline_.push_back(Stage::ShapeMemory);
  if (m.strain.count() > 0) pipeline_.push_back(Stage::StrainMemory);
  if (m.tets.count() > 0) pipeline_.push_back(Stage::TetElastic);
  if (m.shells.triangle_count() > 0) pipeline_.push_back(Stage::ShellElastic);
  if (damped) pipeline_.push_back(Stage::DampingUnshift);
  if (!m.fibre_pairs.empty()) pipeline_.push_back(Stage::ActiveFibres);
  if (tools) pipeline_.push_back(Stage::ToolForces);
  if (rigid) pipeline_.push_back(Stage::RigidForces);
  pipeline_.push_back(Stage::Integrate);
  if (rigid) pipeline_.push_back(Stage::RigidIntegrate);
  if (m.tet_pressure.size() > 0) pipeline_.push_back(Stage::TetPressure);  // before the local constraints: they win
  if (!m.fixed.empty() || !m.imposed.empty() || !m.half_spaces.empty())
    pipeline_.push_back(Stage::LocalConstraints);
  if (tools) pipeline_.push_back(Stage::ToolConstraints);
  if (volume) pipeline_.push_back(Stage::Volume);
  pipeline_.push_back(Stage::AdjustVelocity);
  if (m.tets.multirate()) pipeline_.push_back(Stage::TetTickEnd);  // the slow group's closing half kick
  if (m.sleep.enabled()) pipeline_.push_back(Stage::Sleep);  // who sleeps, who wakes (after the velocities)
  pipeline_.push_back(Stage::Check);
  if (tools) pipeline_.push_back(Stage::ToolAfter);
}

bool Simulation::step(double dt, StageProbe* probe) {
  const Model& m = *model_;
  State& s = state_;
  if (s.fault.kind != StepFault::None) return false;
  const double t_end = s.time + dt;  // constraints at the end of the step use its end time
  ctx_->dt = dt;
  ctx_->end_time = t_end;
  if (!in_tick_) {
    ctx_->substep = 0;
    ctx_->substeps = 1;
    ctx_->last_substep = true;
  }
  for (Stage st : pipeline_) {
    if (probe) probe->begin(static_cast<int>(st));
    switch (st) {
      case Stage::ImposedDisplacement: apply_imposed_displacements(m, s, s.time); break;
      case Stage::ToolBoundary: for (auto& t : tools_) t->boundary_conditions(m, s, dt); break;
      case Stage::ExternalForces: clear_and_add_external_forces(m, s, s.time); break;
      case Stage::ShapeMemory: add_shape_memory_forces(m, s); break;
      case Stage::StrainMemory: add_strain_memory_forces(m, s); break;
      case Stage::TetElastic:
        add_tet_elastic_forces(m, s, !m.tets.multirate() ? TetPass::All : ctx_->substep == 0 ? TetPass::TickStart : TetPass::Held,
                               ctx_->substeps);
        break;
      case Stage::ShellElastic: add_shell_elastic_forces(m, s); break;
      case Stage::ActiveFibres: add_active_forces(m, s); break;
      case Stage::ToolForces: for (auto& t : tools_) t->forces(m, s, dt); break;
      case Stage::RigidForces: gather_rigid_forces(m, s); break;
      case Stage::Integrate: integrate(m, s, dt); break;
      case Stage::RigidIntegrate: integrate_rigid_bodies(m, s, dt); break;
      case Stage::TetPressure: project_tet_pressure(m, s, dt); break;
      case Stage::LocalConstraints: apply_local_constraints(m, s, t_end); break;
      case Stage::ToolConstraints: for (auto& t : tools_) t->constraints(m, s, dt); break;
      case Stage::Volume:
        if (!project_volumes(m, s)) return false;
        break;
      case Stage::AdjustVelocity: adjust_velocities(s, dt); break;
      case Stage::Sleep: update_tet_sleep(m, s, ctx_->last_substep); break;
      case Stage::TetTickEnd:
        if (ctx_->last_substep) {
          // the slow group's force at the tick's end is elastic too: damped like the others
          const bool damped = m.stiffness_damping > 0.0;
          if (damped) shift_for_damping(m, s);
          end_tet_tick(m, s, dt * ctx_->substeps);
          if (damped) unshift_for_damping(s);
        }
        break;
      case Stage::DampingShift: shift_for_damping(m, s); break;
      case Stage::DampingUnshift: unshift_for_damping(s); break;
      case Stage::Check:
        s.time = t_end;
        ++s.step;
        if (!check_state(m, s)) return false;
        break;
      case Stage::ToolAfter: for (auto& t : tools_) t->after_step(m, s, dt); break;
    }
    if (probe) probe->end(static_cast<int>(st));
  }
  return true;
}

bool Simulation::tick(StageProbe* probe) {
  const Model& m = *model_;
  const double h = m.dt / m.substeps;
  in_tick_ = true;
  ctx_->substeps = m.substeps;
  bool ok = true;
  for (int i = 0; i < m.substeps && ok; ++i) {
    ctx_->substep = i;
    ctx_->last_substep = i + 1 == m.substeps;
    ok = step(h, probe);
  }
  in_tick_ = false;
  return ok;
}

void serialize_state(State& s, StateIO& io) {
  io.pod(s.time);
  io.pod(s.step);
  io.array(s.x);
  io.array(s.v);
  io.array(s.f);
  io.array(s.x_prev);
  io.array(s.attractor);
  uint64_t nb = s.bodies.size();
  io.pod(nb);
  if (nb != s.bodies.size()) throw std::runtime_error("StateIO: rigid body count differs from the saved state's");
  for (RigidBodyState& b : s.bodies) {
    io.vec(b.com);
    io.quat(b.rot);
    io.vec(b.lin_vel);
    io.vec(b.ang_vel);
    io.vec(b.force);
    io.vec(b.torque);
  }
  io.array(s.target_volume);
  io.array(s.activation);
  io.array(s.volume_grad);
  io.array(s.last_lambda);
  io.array(s.contact);
  io.array(s.triplet_scratch);
  io.array(s.strain_rot);
  io.pod(s.fault.kind);
  io.pod(s.fault.particle);
  io.pod(s.fault.time);
  io.pod(s.fault.value);
  io.pod(s.clamp_count);
  io.array(s.tet_slow_vol);
  io.array(s.tet_slow_f);
  io.pod(s.tet_slow_f_valid);
  if (!s.tet_slow_hold.empty()) io.array(s.tet_slow_hold);  // multi-rate only (the others save none)
  if (!s.asleep.empty()) {  // sleeping tissue (a model without it saves none of this)
    io.array(s.asleep);
    io.array(s.quiet_ticks);
    io.array(s.tet_order);
    io.pod(s.tet_awake_count);
    io.array(s.tet_held_vol);
    io.array(s.tet_held_f);
  }
}

void Simulation::save(std::vector<uint8_t>& out) {
  StateIO io(out, StateIO::Save);
  serialize_state(state_, io);
  for (auto& t : tools_) t->serialize(io);
}

void Simulation::restore(const std::vector<uint8_t>& in) {
  std::vector<uint8_t>& buf = const_cast<std::vector<uint8_t>&>(in);  // Restore mode only reads
  StateIO io(buf, StateIO::Restore);
  serialize_state(state_, io);
  for (auto& t : tools_) t->serialize(io);
  if (io.position() != in.size()) throw std::runtime_error("Simulation::restore: saved state is longer than this simulation's");
  if (!state_.asleep.empty()) {  // the step indexes with these: a damaged file must not reach it
    const int nt = model_->tets.count();
    bool ok = state_.tet_awake_count >= 0 && state_.tet_awake_count <= nt;
    for (int t : state_.tet_order) ok = ok && t >= 0 && t < nt;
    for (uint8_t a : state_.asleep) ok = ok && a <= 1;
    if (!ok) throw std::runtime_error("Simulation::restore: saved sleeping-tissue state is damaged (element list or flags out of range)");
  }
}

uint64_t Simulation::hash() {
  save(scratch_);
  return fnv1a(scratch_.data(), scratch_.size());
}

}  // namespace ps
