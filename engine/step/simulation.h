// Simulation = shared immutable Model + owned State + the instruments (tools) in the scene.
// step() runs one substep of paper Algorithm 1; a stage the scene does not need is not in the
// pipeline (no rigid body -> no rigid stage; no constrained surface -> no volume stage).
// Nothing in step() allocates, logs, reads a clock or touches a file.
#pragma once
#include <memory>
#include <vector>

#include "engine/draw/draw_sink.h"
#include "engine/model/model.h"
#include "engine/contract/command.h"
#include "engine/contract/snapshot.h"
#include "engine/state/state.h"
#include "engine/util/state_io.h"

namespace ps {

// Where a substep sits in its tick, for the tool hooks (Tool::step_context()): a tool that
// averages over a tick or acts once per tick reads it instead of working it out.
struct StepContext {
  double dt = 0.0;                 // this substep [s]
  double end_time = 0.0;           // simulation time at the end of this substep [s]
  int substep = 0;                 // index in the tick, 0-based
  int substeps = 1;                // substeps in the tick
  bool last_substep = true;        // the last substep of the tick (true for a lone step())
};

// Why a command was refused, written by Tool::apply into a fixed buffer (no allocation).
struct CommandRefusal {
  char text[120] = {0};
  void set(const char* msg);
};

// Optional per-stage probe (the realtime loop's profiler): Simulation::step calls begin/end
// around each stage when one is given. The clock is read by the probe, outside engine/step.
class StageProbe {
 public:
  virtual ~StageProbe() = default;
  virtual void begin(int stage) = 0;
  virtual void end(int stage) = 0;
};

// An instrument or effect that joins the pipeline (needle, probe, organ filling). Each hook runs
// once per substep at its place in Algorithm 1. A tool keeps its own mutable state; it must be
// deterministic and must not allocate inside these hooks. Every mutable quantity of a tool is
// walked by serialize(), so Simulation::save/restore/hash cover the whole simulation.
class Tool {
 public:
  virtual ~Tool() = default;
  virtual const char* name() const = 0;
  // --- live use (between ticks, on the physics thread) ---
  // Applies a command addressed to this tool (engine/contract/command.h). False, with the reason
  // in `why`, when refused (the physics goes on). The default refuses everything.
  virtual bool apply(const Command&, const Model&, const State&, CommandRefusal& why) {
    why.set("this tool takes no command");
    return false;
  }
  // Whether this tool handles commands of this kind (routing of commands with tool = -1).
  virtual bool accepts(CommandKind) const { return false; }
  // Index of the instrument called `name` inside this tool (needle name), -1 if none.
  virtual int find_item(const char* /*name*/) const { return -1; }
  // Saves, restores or hashes every mutable quantity (engine/util/state_io.h).
  virtual void serialize(StateIO&) {}
  // Read-out for panels (one per tool, engine/contract/snapshot.h). Default: the name only.
  virtual void readout(ToolReadout&, const Model&, const State&) const {}
  // Appends the events after `cursor` (a count the tool defines), while `out` holds fewer than
  // `max_size`, and returns the cursor of the first event not appended: events past the bound wait
  // for the next call instead of growing `out` (the physics thread's snapshot buffers are sized
  // once; a burst of events is delivered over several snapshots, in order, none lost while the
  // tool's ring still holds it).
  virtual int64_t events_since(int64_t cursor, int /*tool_index*/, std::vector<SnapshotEvent>&, size_t /*max_size*/) const {
    return cursor;
  }
  // Where the current substep sits in its tick (valid inside the hooks).
  const StepContext& step_context() const { return *ctx_; }

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

 private:
  friend class Simulation;
  static const StepContext kLoneStep;
  const StepContext* ctx_ = &kLoneStep;
};

// The stages of a substep, in the order build_pipeline runs them (Algorithm 1: boundary
// conditions, forces, integrate, constraints, velocity adjust, check); a pipeline holds only
// those the model and its tools need.
enum class Stage : uint8_t {
  ImposedDisplacement, ToolBoundary, ExternalForces,
  DampingShift,  // Model::stiffness_damping: the elastic stages up to DampingUnshift see x + beta v
  ShapeMemory, StrainMemory, TetElastic, ShellElastic, DampingUnshift, ActiveFibres, ToolForces, RigidForces,
  Integrate, RigidIntegrate, TetPressure, LocalConstraints, ToolConstraints, Volume,
  AdjustVelocity, TetTickEnd, Sleep, Check, ToolAfter  // ToolAfter is the last (kStageCount)
};
inline constexpr int kStageCount = static_cast<int>(Stage::ToolAfter) + 1;
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
  bool step(double dt, StageProbe* probe = nullptr);
  // One tick = model.substeps substeps of model.dt / substeps.
  bool tick(StageProbe* probe = nullptr);

  // Whole-simulation snapshot: State plus every tool's serialize() (between ticks).
  void save(std::vector<uint8_t>& out);
  // Restores a save() of a simulation built from the same scenario (same sizes; throws otherwise).
  void restore(const std::vector<uint8_t>& in);
  // FNV-1a over save(): positions, velocities, every other State field (strain warm start,
  // target volumes, ...) and every tool's mutable state. Bit-identical simulations hash equal.
  uint64_t hash();

  const std::vector<Stage>& pipeline() const { return pipeline_; }

 private:
  void build_pipeline();
  std::shared_ptr<const Model> model_;
  State state_;
  std::vector<std::unique_ptr<Tool>> tools_;
  std::vector<Stage> pipeline_;
  std::unique_ptr<StepContext> ctx_ = std::make_unique<StepContext>();  // stable address for the tools
  bool in_tick_ = false;
  std::vector<uint8_t> scratch_;   // save buffer of hash(), reused
};

// Walks every mutable field of State (save/restore/hash; scratch buffers included so a restore
// gives the very same bits as the run that saved).
void serialize_state(State& s, StateIO& io);

}  // namespace ps
