// Everything that changes while simulating. Owned by the physics thread; the renderer sees only
// snapshots. make_state() sizes every buffer once so step() never allocates.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "engine/model/model.h"

namespace ps {

struct RigidBodyState {
  Vec3 com = Vec3::Zero();         // centre of mass [m]
  Quat rot = Quat::Identity();     // body-to-world rotation
  Vec3 lin_vel = Vec3::Zero();     // [m/s]
  Vec3 ang_vel = Vec3::Zero();     // world frame [rad/s]
  Vec3 force = Vec3::Zero();       // accumulated this step [N]
  Vec3 torque = Vec3::Zero();      // accumulated this step [N m]
};

// First problem found by the numerical check; the step stops and reports it.
struct StepFault {
  enum Kind : uint8_t { None, NotFinite, TooFast, TooFar, VolumeSolve } kind = None;
  int particle = -1;               // offending particle (-1 if not particle-specific)
  double time = 0.0;               // simulation time [s]
  double value = 0.0;              // speed [m/s] or excursion [m]
  std::string describe(const Model& m) const;
};

// Values the shape-memory stage keeps per triplet lane (Model::chunks) between its attractor and
// gradient passes (State::triplet_scratch): e_j, e_k, n (3 each), b/|n|, 1/|n|^2.
inline constexpr int kTripletScratchFields = 11;

struct State {
  double time = 0.0;               // [s]
  int64_t step = 0;                // substeps taken
  std::vector<Vec3> x;             // [n] positions [m]
  std::vector<Vec3> v;             // [n] velocities [m/s]
  std::vector<Vec3> f;             // [n] force accumulator [N]
  std::vector<Vec3> x_prev;        // [n] positions at start of the step (velocity adjust)
  std::vector<Vec3> x_shift;       // [n] stiffness damping scratch (Model::stiffness_damping > 0): the
                                   // positions x + beta v the elastic stages see, or the true positions
                                   // while they run (swapped with x; not saved, not hashed) [m]
  std::vector<Vec3> attractor;     // [n] last attractor P* (shape-memory stage output) [m]
  std::vector<RigidBodyState> bodies;   // [rigid bodies]
  std::vector<double> target_volume;    // [surfaces] current target volume [m^3]
  std::vector<double> activation;       // [components] in [0,1]
  std::vector<Vec3> volume_grad;        // [n] scratch: volume gradient
  std::vector<double> last_lambda;      // [surfaces] last volume multiplier (diagnostic)
  std::vector<uint8_t> contact;         // [n] scratch: axis mask pinned this step by a
                                        // half-space or a tool contact (volume leaves it alone)
  std::vector<double> triplet_scratch;  // scratch of the shape-memory stage: per triplet lane of
                                        // one particle its edges, normal, b/|n| and 1/|n|^2
                                        // (kTripletScratchFields x 4 x Model::most_chunks)
  std::vector<Quat> strain_rot;         // [strain clusters] rotation of the polar decomposition of
                                        // the cluster's F at the last substep (warm start)
  std::vector<double> tet_node_vol;     // [Model::tets.nodes] scratch: current volume share of each
                                        // tet node, then its pressure kappa (J_n - 1) [m^3] / [Pa]
  std::vector<double> tet_quarter;      // [Model::tets elements + 1] scratch: each element's volume share
                                        // V_t / 4 [m^3] (the node volumes gather them, tet_elastic.cpp)
  std::vector<double> tet_edges;        // [9 Model::tets elements] scratch: each element's edges x_{j+1} - x_0
                                        // as the node volumes measured them, for the force pass [m]
  std::vector<double> tet_slow_vol;     // [Model::tets.nodes] multi-rate scratch: volume share of the
                                        // slow elements at the tick's first substep [m^3]
  std::vector<Vec3> tet_slow_f;         // [n] multi-rate (symmetric split): the slow elements' force at
                                        // the end of the last tick, the next tick's opening half kick [N]
  uint8_t tet_slow_f_valid = 0;         // 1 once tet_slow_f holds the force at the current positions
  std::vector<Vec3> tet_slow_hold;      // [n] multi-rate: the held part of the slow force, applied as a
                                        // steady force on every substep (the kicks carry the rest); it
                                        // follows tet_slow_f tick by tick (end_tet_tick) [N]
  // implicit pressure scratch (Model::tet_pressure; overwritten before use every substep, so not
  // part of save() or the state hash)
  std::vector<double> pressure_rhs;     // [k] right-hand side, then the multiplier step [m^3] / [kg/m]
  std::vector<double> pressure_work;    // [k] triangular-solve scratch
  std::vector<double> pressure_lambda;  // [k] multiplier accumulated over the substep's solves [kg/m]
  std::vector<Vec3> pressure_dx;        // [n] position correction of the support particles [m kg]
  std::vector<double> pressure_quarter; // [TetPressure::tets] volume share V_t / 4 of each of the
                                        // pressure's elements [m^3]
  // sleeping tissue (Model::sleep; empty when it is off). Part of save() and the hash: which
  // elements run, and the held shares and forces of those that do not, decide the next step.
  std::vector<uint8_t> asleep;          // [n] 1: the particle sleeps (not integrated, v = 0)
  std::vector<uint16_t> quiet_ticks;    // [n] tick ends in a row an awake eligible particle was balanced and at rest
  std::vector<int> tet_order;           // [tet elements] the evaluated elements ascending, then the held ones ascending
  int tet_awake_count = 0;              // how many of tet_order are evaluated
  std::vector<double> tet_held_vol;     // [Model::tets.nodes] volume shares of the held elements [m^3]
  std::vector<Vec3> tet_held_f;         // [n] force of the held elements when they were last evaluated [N]
  StepFault fault;
  int64_t clamp_count = 0;         // times a safety clamp acted
};

State make_state(const Model& model);

// FNV-1a hash over the raw bytes of positions, velocities and rigid poses: bit-identical
// states hash equal (determinism tests, replay checks).
uint64_t hash_state(const State& s);

double kinetic_energy(const Model& m, const State& s);   // [J]
double max_speed(const State& s);                        // [m/s]

}  // namespace ps
