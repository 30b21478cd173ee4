// Simulation = shared immutable Model + owned State + the instruments (tools) in the scene.
// step() runs one substep of paper Algorithm 1; a stage the scene does not need is not in the
// pipeline (no rigid body -> no rigid stage; no constrained surface -> no volume stage).
// Nothing in step() allocates, logs, reads a clock or touches a file.
#pragma once
#include <memory>
#include <vector>

#include "engine/draw/draw_sink.h"
#include "engine/model/model.h"
#include "engine/state/state.h"

namespace ps {

// An instrument or effect that joins the pipeline (needle, probe, organ filling). Each hook runs
// once per substep at its place in Algorithm 1. A tool keeps its own mutable state; it must be
// deterministic and must not allocate inside these hooks.
class Tool {
 public:
  virtual ~Tool() = default;
  virtual const char* name() const = 0;
  // before forces: imposed displacements, target volumes, kinematic poses
  virtual void boundary_conditions(const Model&, State&, double /*dt*/) {}
  // after internal forces: tool forces on particles (and reactions on the tool)
  virtual void forces(const Model&, State&, double /*dt*/) {}
  // after local constraints, before the volume projection: contacts (set State::contact)
  virtual void constraints(const Model&, State&, double /*dt*/) {}
  // after the check: events, read-outs
  virtual void after_step(const Model&, State&, double /*dt*/) {}
  // outside the step (render/UI thread side of a snapshot): describe the tool's geometry
  // (engine/draw/draw_sink.h). Must not change the tool.
  virtual void draw(DrawSink&, const Model&, const State&) const {}
};

enum class Stage : uint8_t {
  ImposedDisplacement, ExternalForces, ShapeMemory, StrainMemory, TetElastic, ActiveFibres, ToolBoundary, ToolForces,
  RigidForces, Integrate, RigidIntegrate, LocalConstraints, ToolConstraints, Volume,
  AdjustVelocity, Check, ToolAfter
};
const char* stage_name(Stage s);

class Simulation {
 public:
  explicit Simulation(std::shared_ptr<const Model> model);

  const Model& model() const { return *model_; }
  std::shared_ptr<const Model> model_ptr() const { return model_; }
  State& state() { return state_; }
  const State& state() const { return state_; }

  // Adds a tool and rebuilds the pipeline (not during a step).
  void add_tool(std::unique_ptr<Tool> tool);
  const std::vector<std::unique_ptr<Tool>>& tools() const { return tools_; }

  // One substep of length dt [s]. Returns false (and leaves state().fault set) when the check
  // finds NaN/Inf or a blow-up; the state is then not advanced further by later calls.
  bool step(double dt);
  // One tick = model.substeps substeps of model.dt / substeps.
  bool tick();

  const std::vector<Stage>& pipeline() const { return pipeline_; }

 private:
  void build_pipeline();
  std::shared_ptr<const Model> model_;
  State state_;
  std::vector<std::unique_ptr<Tool>> tools_;
  std::vector<Stage> pipeline_;
};

}  // namespace ps
