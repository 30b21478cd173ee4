// The stages of one physics substep (paper Algorithm 1), one file each:
//   boundary conditions -> forces -> integrate -> constraints (local, volume) -> velocity adjust
//   -> check. None of them allocates, logs or touches files.
#pragma once
#include "engine/model/model.h"
#include "engine/state/state.h"

namespace ps {

// constraints.cpp: imposed displacements at time t (boundary conditions, before forces)
void apply_imposed_displacements(const Model& m, State& s, double t);
// forces.cpp: clears the accumulator, adds gravity and locally applied forces at time t
void clear_and_add_external_forces(const Model& m, State& s, double t);
// shape_memory.cpp: shape-memory force k_e (P* - P) and its redistribution (paper §3.2)
void add_shape_memory_forces(const Model& m, State& s);
// strain_memory.cpp: strain-memory force of every cluster in Model::strain (docs/model.md);
// polar_iterations caps the rotation iterations (0: the stage's default, warm-started)
void add_strain_memory_forces(const Model& m, State& s, int polar_iterations = 0);
// strain_memory.cpp: the energy sum_c E_c whose negative gradient that force is [J] (tests,
// diagnostics; not used in the step), with each cluster's rotation converged from s.strain_rot
double strain_memory_energy(const Model& m, const State& s);
// tet_elastic.cpp: elastic force of the tet model's elements (Model::tets, docs/model.md "Tet
// model"): per-element isochoric neo-Hookean shear, per-node averaged volumetric pressure
// Which elements and how (multi-rate, TetElements::fast_count): All evaluates every element now;
// TickStart (a tick's first substep) adds the fast elements' force and the slow ones' whole-tick
// impulse as substeps x their force, and keeps the slow elements' volume shares in State; Held
// (the tick's other substeps) evaluates only the fast elements; FastOnly / SlowOnly give one
// group's force at the current volumes (the stability estimates).
enum class TetPass { All, TickStart, Held, FastOnly, SlowOnly };
void add_tet_elastic_forces(const Model& m, State& s, TetPass pass = TetPass::All, int substeps = 1);
// tet_elastic.cpp: multi-rate only, after the tick's last substep: the slow elements' force at the
// tick's end positions (kept in State for the next tick's opening kick) and its closing half kick
// v += T/2 F / m on every free axis; tick = the tick's length T [s]
void end_tet_tick(const Model& m, State& s, double tick);
// tet_elastic.cpp: the energy whose negative gradient that force is [J] (tests, diagnostics)
double tet_elastic_energy(const Model& m, const State& s);
// shell_elastic.cpp: elastic force of the shell model's membranes (Model::shells, docs/model.md
// "Shell model"): co-rotational constant-strain triangles (plane stress) and dihedral hinges
void add_shell_elastic_forces(const Model& m, State& s);
// shell_elastic.cpp: the same per part, for triangles / hinges [begin, end), added to f (blocks of
// eight where the CPU has AVX-512, else four, run as vectors, the rest scalar; all give the same bits)
void add_shell_membrane_forces(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f);
void add_shell_hinge_forces(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f);
// their two vector widths (the functions above pick one; tests compare both with the scalar pass):
// four per vector (any x86-64), eight (only where tet_element_forces8_available())
void shell_membrane_forces4(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f);
void shell_membrane_forces8(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f);
void shell_hinge_forces4(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f);
void shell_hinge_forces8(const ShellElements& sh, const Vec3* x, int begin, int end, Vec3* f);
// shell_elastic.cpp: the energy whose negative gradient that force is [J] (tests, diagnostics)
double shell_elastic_energy(const Model& m, const State& s);
// active.cpp: fibre contraction of active components scaled by State::activation
void add_active_forces(const Model& m, State& s);
// rigid.cpp: moves forces of attached elastic particles onto their rigid bodies
void gather_rigid_forces(const Model& m, State& s);
// tet_sleep.cpp: sleeping tissue (Model::sleep), after the velocity adjustment of every substep:
// a sleeping particle that a load reached wakes; at a tick's end (tick_end) an awake one that has
// been balanced and at rest for Model::sleep.hold_ticks falls asleep. When either happens the
// evaluated elements and the held shares and forces are rebuilt (rebuild_tet_sleep).
void update_tet_sleep(const Model& m, State& s, bool tick_end);
// tet_sleep.cpp: State::tet_order from State::asleep, and the held elements' volume shares and
// forces at the current positions
void rebuild_tet_sleep(const Model& m, State& s);
// tet_elastic.cpp: elements list[0..count) (ascending) add their volume shares V_t / 4 to vol
// (indexed like Model::tets.nodes) [m^3]
void add_tet_node_volumes(const TetElements& te, const Vec3* x, const int* list, int count, double* vol);
// tet_elastic.cpp: q[t] = V_t / 4 of the elements [begin, end) whose four particles are
// vv[4 t .. 4 t + 3] [m^3]: TetElements::v (the node volumes gather them) or the implicit
// pressure's contiguous copy TetPressure::tet_v
// edges (optional): the elements' edges x_{j+1} - x_0 too, coordinate r of edge j of element t at
// edges[(3 j + r) stride + t] [m] (the element pass reads them instead of the positions)
void tet_quarters(const int* vv, const Vec3* x, int begin, int end, double* q, double* edges = nullptr, size_t stride = 0);
// tet_pressure.cpp: the implicit pressure's correction before the mass weighting, dx += J^T dl,
// for the elements [0, ntp) of TetPressure::tet_v / tet_row (dl [k] the multiplier step [kg/m],
// dx [m kg]); four elements per vector, the same bits as one element at a time
void pressure_corrections(const int* tv, const int* trow, int ntp, const double* dl, const Vec3* x, Vec3* dx);
// tet_elastic.cpp: adds the volume shares of the elements [begin, end) to vol [m^3], gathered per
// node when the range is the fast group, the slow group or all (q: [nt + 1] scratch, q[nt] = -0.0,
// the gather's padding), else scattered;
// the same bits as add_tet_node_volumes over the same elements. edges (optional, [9 nt], stride nt):
// the gathered ranges' edges as tet_quarters writes them; true when it wrote them
bool add_tet_range_volumes(const TetElements& te, const Vec3* x, int begin, int end, double* q, double* vol,
                           double* edges = nullptr);
// tet_elastic.cpp: node volume shares vol [m^3] -> node pressures kappa (J_n - 1) [Pa], in place
void tet_node_pressures(const TetElements& te, double* vol);
// tet_elastic.cpp: the force of elements list[0..count), with node pressures p [Pa], added to f
void add_tet_element_forces(const TetElements& te, const Vec3* x, const double* p, const int* list, int count, Vec3* f);
// tet_elastic.cpp: the same for elements list[begin..end) (list null: the elements begin..end-1
// themselves, read from TetElements::g4 from the first block boundary on), forces times scale
void tet_element_forces(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end, double scale,
                        Vec3* f, const double* ed = nullptr);
// its two vector widths (tet_element_forces picks one; tests compare both with the scalar pass):
// four elements per vector (any x86-64), eight (only where tet_element_forces8_available())
void tet_element_forces4(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end, double scale,
                         Vec3* f, const double* ed = nullptr);
void tet_element_forces8(const TetElements& te, const Vec3* x, const double* p, const int* list, int begin, int end, double scale,
                         Vec3* f, const double* ed = nullptr);
bool tet_element_forces8_available();
// stiffness_damping.cpp: Rayleigh stiffness damping (Model::stiffness_damping = beta): State::x
// becomes x + beta v for the elastic stages that follow (the true positions wait in State::x_shift)
// until unshift_for_damping swaps them back
void shift_for_damping(const Model& m, State& s);
void unshift_for_damping(State& s);
// integrate.cpp: symplectic Euler with implicit velocity damping v /= (1 + c dt)
void integrate(const Model& m, State& s, double dt);
// tet_pressure.cpp: the implicit nodal pressure of `pressure: implicit` tet nodes (Model::tet_pressure)
// as a backward-Euler constraint step on the integrated positions, substep dt [s]
void project_tet_pressure(const Model& m, State& s, double dt);
// rigid.cpp: integrates dynamic bodies, places rigid and attached particles on their bodies
void integrate_rigid_bodies(const Model& m, State& s, double dt);
// constraints.cpp: fixed axes, imposed displacements, half-spaces (local constraints)
void apply_local_constraints(const Model& m, State& s, double t);
// volume.cpp: exact volume projection of every constrained surface (paper §3.3); false if a
// surface has no real solution (fault recorded in s.fault)
bool project_volumes(const Model& m, State& s);
// integrate.cpp: v = (x - x_prev)/dt so constraint corrections become velocities
void adjust_velocities(State& s, double dt);
// check.cpp: NaN/Inf, speed and excursion limits; false and s.fault set on the first problem
bool check_state(const Model& m, State& s);

// volume.cpp: 6 x enclosed volume of a surface at positions x, and its exact cubic along g
double surface_volume(const Surface& surf, const std::vector<Vec3>& x);

}  // namespace ps
