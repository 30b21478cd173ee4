// The compiled, immutable description of a scene (paper §3.1): particles with neighbourhoods,
// components, surfaces, constraints. Built once by compile_scenario(); never changed by step().
// Every mutable quantity lives in State (engine/state/state.h).
//
// Shape memory (paper §3.2.3). For particle p with neighbours N_1..N_n and m valid triplets t,
//   P*_p = (1/m) sum_t (alpha_t^i N_i + alpha_t^j N_j + alpha_t^k N_k + beta_t n_t/|n_t|)
// The linear part collapses to one weight per neighbour, w_pj = (1/m) sum_{t∋j} alpha_t^j
// (sum_j w_pj = 1), and only triplets with beta_t != 0 need a normal at run time; they are kept
// with b_t = beta_t/m [m].
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/model/role.h"
#include "engine/util/vec.h"

namespace ps {

// How the opposite of the shape-memory force reaches the neighbours (shape_memory.cpp).
enum class Redistribution : uint8_t {
  Gradient,  // exact gradient of sum 1/2 k_e |P*-P|^2 (default: conservative, stable)
  Linear     // paper §3.2.3 literally: by the linear coefficients only (reference)
};

enum class ComponentKind : uint8_t { Elastic, Rigid, Active };

struct Component {
  std::string name;
  ComponentKind kind = ComponentKind::Elastic;
  Role role = Role::Other;         // `role:`, else default_role() of the name (engine/model/role.h)
  int first_particle = 0;          // particles of a component are contiguous
  int particle_count = 0;
  int surface = -1;                // index into Model::surfaces, -1 if none
  double spacing = 0.0;            // particle spacing h [m]
  bool volumetric = true;          // interior particles present (false: surface-only)
  // active components (muscle): contraction along fibre, scaled by State::activation
  Vec3 fibre_dir = Vec3::UnitZ();  // unit fibre direction (rest frame)
  double active_force = 0.0;       // force of one fibre pair at activation 1 [N]
  int rigid_body = -1;             // index into Model::rigid_bodies for rigid components
};

// Triplet whose offset beta along the triangle normal is non-zero (needs a normal each step).
struct BetaTriplet {
  int i, j, k;                     // neighbour particle indices (global)
  double b;                        // beta_t / m_p [m], signed along (N_j-N_i)x(N_k-N_i)
};

// --- shape-memory chunk layout (engine/model/triplet_chunks.h; read by engine/step/shape_memory.cpp) ---
// The beta triplets of a particle regrouped so the stage runs 4 triplets per SIMD chunk with few
// loads: a chunk is two half-chunks h = 0, 1, each the two triplets (a_h, b_h, c_h) and
// (a_h, b_h, c_h + 1) of neighbour slots (slots index the particle's neighbour list, in nbr
// order). A triplet's vertices may be rotated cyclically (the same normal); b_t = 0 in a lane
// that holds no beta triplet, which adds exactly zero.
struct TripletChunk {
  uint8_t a[2], b[2], c[2];        // neighbour slots of half-chunk 0 and 1
  uint8_t a4[2], b4[2], c4[2];     // the same slots times 4 (offsets of 4-double accumulators)
};

// A closed triangulated surface over particles: volume constraint (§3.3) and rendering.
struct Surface {
  int component = -1;
  std::vector<int> vertices;                   // [nv] particle indices on the surface
  std::vector<std::array<int, 3>> faces;       // [nf] particle indices, outward CCW
  double rest_volume = 0.0;                    // V0 at compile [m^3]
  bool volume_constrained = false;
  // vertex-to-face incidence (CSR over vertices) for the volume gradient
  std::vector<int> vert_face_start;            // [nv+1]
  std::vector<int> vert_face;                  // face indices
};

// A dynamic or kinematic rigid body made of the particles of a rigid component.
struct RigidBody {
  int component = -1;
  double mass = 0.0;               // [kg]
  Mat3 inertia_body = Mat3::Identity();  // about the centre of mass, body frame [kg m^2]
  Vec3 com_rest = Vec3::Zero();    // centre of mass at rest [m]
  bool kinematic = true;           // true: pose only changes by command (bones, plates)
  std::vector<int> particles;      // rigid particles
  std::vector<Vec3> local;         // [particles] offset from com in body frame [m]
};

// Elastic particle doubled with a rigid body: held coincident with a point fixed in the body
// (paper §3.1: "border particles ... doubled but constrained to be at the same position").
struct RigidAttachment {
  int particle;                    // elastic particle
  int body;                        // RigidBody index
  Vec3 local;                      // offset from body com in body frame [m]
};

// Per-axis fixed particle (axis mask bit 0=x, 1=y, 2=z), held at its rest coordinate.
struct FixedParticle { int particle; uint8_t axes; };

// Imposed displacement following a ramp: u(t) = by * clamp((t - t0)/(t1 - t0), 0, 1).
struct ImposedDisplacement {
  std::vector<int> particles;
  Vec3 by = Vec3::Zero();          // total displacement [m]
  uint8_t axes = 7;                // only these axes are imposed (others stay free)
  double t0 = 0.0, t1 = 0.0;       // ramp start/end [s]
};

// Particles kept on the side of a plane where (x - point).normal >= 0.
struct HalfSpace {
  std::vector<int> particles;
  Vec3 point = Vec3::Zero();       // [m]
  Vec3 normal = Vec3::UnitZ();     // unit
};

// Locally applied force spread evenly on particles, ramped like ImposedDisplacement.
struct AppliedForce {
  std::vector<int> particles;
  Vec3 total = Vec3::Zero();       // total force at full ramp [N]
  double t0 = 0.0, t1 = 0.0;       // ramp [s]
};

// Strain memory (engine/step/strain_memory.cpp, docs/model.md): one cluster per particle of a
// `model: strain` material = the particle plus its neighbours. Per cluster c with members i, rest
// offsets d0_i from the rest centroid, S = sum d0 d0^T, q_i = S^-1 d0_i, current centroid x_c:
//   F = sum_i (x_i - x_c) g_i^T   (g = q + a correction orthogonal to affine motions, so that a
//                                  uniform stress is exactly in equilibrium: strain_clusters.cpp)
//   F_ls = sum_i (x_i - x_c) q_i^T (least-squares affine fit);  r_i = x_i - x_c - F_ls d0_i
//   R = rotation of the polar decomposition of F,  J = det F
//   E_c = mu2v/2 |F - R|^2 + k_v/2 (J - 1)^2 + k_r/2 sum_i |r_i|^2
// Small strain: mu2v/2 = mu V_c and k_v = lambda V_c give the energy density mu|eps|^2 +
// lambda/2 (tr eps)^2 of an isotropic linear material (V_c: the particle's volume); k_r resists
// the non-affine rest of the cluster's motion (hourglass modes).
struct StrainClusters {
  std::vector<int> centre;         // [nc] the particle the cluster belongs to
  std::vector<int> start;          // [nc+1] CSR into member/d0/q
  std::vector<int> member;         // [nnz] particle index (centre first)
  std::vector<Vec3> d0;            // [nnz] rest offset from the rest centroid [m]
  std::vector<Vec3> q;             // [nnz] S^-1 d0: least-squares fit weights [1/m]
  std::vector<Vec3> g;             // [nnz] q + consistency correction: gradient weights of F [1/m]
  std::vector<double> mu2v;        // [nc] 2 mu V_c [N m]
  std::vector<double> k_v;         // [nc] lambda V_c [N m]
  std::vector<double> k_r;         // [nc] non-affine (residual) stiffness [N/m]
  int count() const { return static_cast<int>(centre.size()); }
};

// Tetrahedral elements of the v2 tissue model (material `model: tet`, docs/model.md "Tet model"):
// a Delaunay tetrahedralisation of the particles, built once at compile time by
// build_tet_elements (engine/model/tet_elements.cpp); the force is engine/step/tet_elastic.cpp.
// Structure of arrays, rest data precomputed: the step only reads these.
struct TetElements {
  std::vector<int> v;              // [4 nt] particle indices, positively oriented at rest
  std::vector<double> g;           // [9 nt] rows g1, g2, g3 of Dm^-1 (Dm = [x1-x0, x2-x0, x3-x0] at
                                   // rest): F = sum_i (x_i - x_0) g_i^T [1/m]
  std::vector<double> vol0;        // [nt] rest volume V0 [m^3]
  std::vector<double> mu;          // [nt] shear modulus mu of the element [Pa]
  // g again, in blocks of four elements for the 4-lane element pass: g4[36 b + 4 i + l] is entry
  // i of g for element 4 b + l (zero past the last element); one vector load per entry instead of
  // four scalar ones. Built by pack_tet_blocks after the last change to g (compile_scenario);
  // empty: the pass gathers from g.
  std::vector<double> g4;
  // The elements around each node, as the node volumes gather them (pack_tet_blocks), four nodes
  // at a time (bundle b: nodes 4b .. 4b + 3), for each range r (0: all elements, 1: the fast group
  // [0, fast_count), 2: the slow group): row j of bundle b holds each of its four nodes' j-th
  // element of the range, ascending (the scatter's order), padded past a node's last one with
  // element nt, whose slot of State::tet_quarter holds -0.0 (x + -0.0 == x exactly, for every x,
  // so padding changes no bit); rows gather_start[r][b] .. gather_start[r][b + 1], 4 entries each.
  // Four nodes' sums run side by side instead of one node's chain of dependent additions at a time.
  std::vector<int> gather_start[3];  // [bundles + 1] rows
  std::vector<int> gather_elem[3];   // [4 rows] element indices
  int gather_ranges() const { return gather_start[0].empty() ? 0 : 3; }
  std::vector<int> nodes;          // particles touched by some element, ascending
  std::vector<double> node_inv_vol0;  // [nodes] 1 / (sum of V0/4 over the node's elements) [1/m^3]
  std::vector<double> node_kappa;  // [nodes] volumetric modulus lambda + mu of the node's particle [Pa]
  std::vector<int> node_slot;      // [n particles] index into nodes, -1 when untouched
  // pressure: implicit (TetPressure): the node's volumetric term is a constraint solved after
  // integration, not a force; node_kappa_explicit is node_kappa, or 0 for those nodes (the
  // force passes and the stability estimates read it; the energy reads node_kappa)
  std::vector<uint8_t> node_implicit;       // [nodes] 1: the node's pressure is implicit
  std::vector<double> node_kappa_explicit;  // [nodes] kappa of the explicit force [Pa]
  // Multi-rate (solver.multirate, compile.cpp partition_tet_rates): elements [0, fast_count) are
  // evaluated every substep; the rest touch only particles whose own stable step admits the whole
  // tick, so their force is evaluated once per tick and applied as the tick's impulse
  // (engine/step/tet_elastic.cpp, TetPass::TickStart).
  // fast_count == count() when the scene has no slow element.
  int fast_count = 0;
  int count() const { return static_cast<int>(vol0.size()); }
  bool multirate() const { return fast_count < count(); }
};

// Implicit nodal pressure of the tet model (materials with `pressure: implicit`; docs/model.md
// "Implicit pressure"; built by build_tet_pressure, engine/model/tet_pressure.cpp, solved by
// engine/step/tet_pressure.cpp). Each such node n has the compliant constraint
//   C_n(x) = V_n(x) - V0_n,  compliance alpha_n = V0_n / kappa_n,
// whose energy C^2 / (2 alpha) is the explicit term 1/2 kappa V0 (J_n - 1)^2. After integration,
// each substep h solves the linearised backward-Euler (XPBD) step
//   (J W J^T + alpha / h^2) dlambda = -C(x) - alpha/h^2 lambda,   x += W J^T dlambda,
// with J = dC/dx and W the inverse inertial masses (0 on fixed axes). The matrix is taken at rest
// and factored once (sparse LDL^T, fill-reducing order): the pressure wave, which would set an
// explicit substep at nu 0.49, does not limit it, and the solve is exact in one step for a linear
// constraint; `iterations` re-linearise at the current positions.
struct TetPressure {
  std::vector<int> row_slot;       // [k] tet node slot (TetElements::nodes index) of row r, ascending
  std::vector<int> slot_row;       // [tet nodes] row of the slot, -1: explicit node
  std::vector<int> tets;           // elements with at least one implicit node, ascending
  std::vector<int> tet_v;          // [4 tets] their particles (TetElements::v), contiguous for the step
  std::vector<int> tet_row;        // [4 tets] the row of each of their nodes, -1: explicit node
  std::vector<int> particles;      // particles of those elements, ascending (the correction's support)
  std::vector<double> vol0;        // [k] rest volume share V0_n [m^3]
  std::vector<double> alpha;       // [k] compliance V0_n / kappa_n [m^5/N]
  double h = 0.0;                  // substep the factor was built for [s] (alpha / h^2 on its diagonal)
  int iterations = 1;              // linearised solves per substep
  // A = P^T L D L^T P: perm[i] is the system row at position i of the factored order; L unit lower
  // triangular, strictly-lower entries by column (CSC)
  std::vector<int> perm;           // [k]
  std::vector<int> l_start;        // [k + 1]
  std::vector<int> l_row;          // [nnz]
  std::vector<double> l_val;       // [nnz] [-]
  std::vector<double> d;           // [k] [m^4/kg]
  int size() const { return static_cast<int>(row_slot.size()); }
};

// Sleeping tissue (solver.sleep, docs/model.md "Sleeping tissue"; compiled by compile_sleep,
// engine/scenario/compile_sleep.cpp; stepped by engine/step/tet_sleep.cpp). A tet particle at
// rest and in balance falls asleep: it is not integrated, and a tet element whose four nodes all
// sleep is not evaluated (its volume shares and forces are held from when it fell asleep). A
// sleeping particle wakes as soon as a load reaches it: its unbalanced force (the evaluated
// elements, the held ones, gravity, tools) exceeds mass x wake_accel, or a constraint moves it.
// Eligible: particles of tet components with explicit pressure that nothing else moves directly
// (not on a volume-constrained surface, not in the implicit pressure's support, not fixed).
struct TetSleep {
  enum Role : uint8_t { kAwake = 0, kMaySleep = 1, kFixed = 2 };
  std::vector<uint8_t> role;       // [n particles] kAwake: never sleeps; kMaySleep; kFixed: held on
                                   // every axis by a fixed constraint, counts as asleep for its
                                   // elements. Empty: sleeping is off
  double wake_accel = 0.0;         // unbalanced force / mass that wakes a sleeping particle [m/s^2]
  double sleep_accel = 0.0;        // ... below which an awake one counts as balanced [m/s^2]
  double sleep_speed = 0.0;        // ... and its speed as at rest [m/s]
  int hold_ticks = 0;              // tick ends in a row balanced and at rest before it sleeps
  int eligible_count = 0;          // particles with role kMaySleep
  bool enabled() const { return !role.empty(); }
};

// Shell elements of membrane components (material `model: shell`, docs/model.md "Shell model"):
// the bladder and rectal walls as thin shells on their own surface triangulation, built once by
// build_shell_elements (engine/model/shell_elements.cpp); the force is engine/step/shell_elastic.cpp.
// Membrane: one co-rotational linear triangle (constant strain) per surface face, plane stress,
// wall thickness t. Bending: one hinge per interior edge (discrete shells, Grinspun et al. 2003),
// energy 1/2 k_h (theta - theta0)^2 with k_h = D 3 |e|^2 / (A1 + A2), D = E t^3 / (12 (1 - nu^2)).
// Structure of arrays, rest data precomputed.
struct ShellElements {
  // triangles [nt]
  std::vector<int> tri;            // [3 nt] particle indices (the surface face, outward CCW)
  std::vector<double> bm;          // [4 nt] Dm^-1 row-major (Dm = rest edges x1-x0, x2-x0 in the
                                   // triangle's own orthonormal 2D frame) [1/m]
  std::vector<double> area_t;      // [nt] rest area x thickness A0 t [m^3]
  std::vector<double> mu;          // [nt] shear modulus [Pa]
  std::vector<double> lambda;      // [nt] plane-stress Lame lambda 2 mu lambda / (lambda + 2 mu) [Pa]
  // hinges [nh]: edge (v[0], v[1]), opposite vertices v[2] (in the face with v0 -> v1 CCW) and v[3]
  std::vector<int> hinge;          // [4 nh] particle indices
  std::vector<double> theta0;      // [nh] rest dihedral angle [rad]
  std::vector<double> rest_cs;     // [2 nh] cos theta0, sin theta0 (the force measures theta - theta0
                                   // as one angle, engine/step/shell_elastic.cpp) [-]
  std::vector<double> k_hinge;     // [nh] bending stiffness [N m]
  int triangle_count() const { return static_cast<int>(area_t.size()); }
  int hinge_count() const { return static_cast<int>(theta0.size()); }
};

// Active fibre pair: contraction force along the current pair direction.
struct FibrePair { int a, b; int component; };

// The urethra as a tube of this radius around Model::urethra [m]: a needle tip inside it is in the
// urethra (the needle's event, the metrics' structure hit) and the urethra's dose-volume indices
// are taken over it. The wall is not modelled; 3 mm is about the distended prostatic urethra.
inline constexpr double kUrethraRadius = 3e-3;

struct Model {
  std::string name;
  std::string source_file;

  // time
  double dt = 1e-3;                // tick [s]
  int substeps = 1;                // physics substeps per tick
  double duration = 1.0;           // default simulated duration [s]
  double leave_margin = 0.05;      // the watchdog's margin outside the rest bounding box [m] (not physics: not hashed)
  Vec3 gravity = Vec3::Zero();     // [m/s^2]
  Redistribution redistribution = Redistribution::Gradient;
  // Triplet selection (solver.triplets): 0 keeps every valid triplet of C(n,3) (the paper's
  // scheme); N > 0 keeps each particle's N best-conditioned ones (smallest bound on |dP*_t/dx|,
  // engine/model/discrete_coordinates.cpp). Fewer triplets cost less per substep and drop the
  // ill-conditioned ones that set the stable substep (docs/performance.md).
  int max_triplets = 0;

  // particles [n]
  std::vector<Vec3> rest_pos;      // [n] rest positions [m]
  std::vector<double> mass;        // [n] [kg]
  std::vector<double> inv_mass;    // [n] [1/kg]; 0 for rigid and kinematic particles
  std::vector<double> k_e;         // [n] shape-memory stiffness [N/m]
  std::vector<double> k_c;         // [n] needle cutting weight [N]
  std::vector<double> k_f;         // [n] needle friction weight [N]
  std::vector<double> damping;     // [n] velocity damping rate [1/s]
  std::vector<int> component_of;   // [n]
  std::vector<uint8_t> on_surface; // [n] 1 if on the component's surface
  std::vector<uint8_t> locked_axes; // [n] axis mask (bit 0=x,1=y,2=z) held by fixed/imposed
                                    // constraints or a rigid body; the volume projection leaves
                                    // these coordinates alone

  // neighbourhoods (CSR): neighbours and their linear coefficient in the attractor
  std::vector<int> nbr_start;      // [n+1]
  std::vector<int> nbr;            // [nnz] neighbour particle index
  std::vector<double> nbr_w;       // [nnz] w_pj (dimensionless, sum_j w_pj = 1)
  std::vector<int> beta_start;     // [n+1]
  std::vector<BetaTriplet> beta;   // triplets with beta != 0
  std::vector<int> triplet_count;  // [n] valid triplets m_p (statistics, check command)
  std::vector<uint8_t> shape_memory; // [n] 1 if the particle carries a shape-memory force
  StrainClusters strain;           // strain-memory clusters (empty: no `model: strain` material)
  TetElements tets;                // tet-model elements (empty: no `model: tet` material)
  TetPressure tet_pressure;        // implicit nodal pressure (empty: no `pressure: implicit` material)
  TetSleep sleep;                  // sleeping tissue (empty: solver.sleep off)
  ShellElements shells;            // shell-model membranes (empty: no `model: shell` material)
  bool any_shape_memory = true;    // some particle has k_e > 0 (else the stage is left out)

  // named particle tags (scenario tags: and prostate_zones:, e.g. "lesion", "base", "peripheral"):
  // bit t of particle_tags[p] is set when particle p carries tag_names[t]
  std::vector<std::string> tag_names;   // [tags] at most 64
  std::vector<Role> tag_roles;          // [tags] `role:` of the tag, else default_role() of its name
  std::vector<uint64_t> particle_tags;  // [n] bit masks; empty when the scene has no tags
  int find_tag(const std::string& t) const {
    for (size_t i = 0; i < tag_names.size(); ++i)
      if (tag_names[i] == t) return static_cast<int>(i);
    return -1;
  }

  std::vector<Component> components;
  // The prostatic urethra's centre line at rest [m] (empty: none): urethra.csv beside the mesh of
  // the gland (the `prostate_zones:` component, else the first component whose role is prostate),
  // placed by the mesh's units, scale, rotation and translation like the mesh itself
  // (engine/scenario/compile_urethra.cpp). The needle's urethra events, the metrics, the
  // ultrasound and the renderer all read this one line.
  std::vector<Vec3> urethra;
  std::vector<Surface> surfaces;
  std::vector<RigidBody> rigid_bodies;
  std::vector<RigidAttachment> attachments;
  std::vector<FixedParticle> fixed;
  std::vector<ImposedDisplacement> imposed;
  std::vector<HalfSpace> half_spaces;
  std::vector<AppliedForce> applied_forces;
  std::vector<FibrePair> fibre_pairs;

  std::vector<std::string> compile_warnings;  // reported by simulate/check

  // --- shape-memory chunk layout (see TripletChunk; built by build_triplet_chunks) ---
  std::vector<int> chunk_start;          // [n+1] chunks of particle p: chunk_start[p] .. chunk_start[p+1]-1
  std::vector<TripletChunk> chunks;
  std::vector<double> chunk_beta;        // [4 per chunk] b_t [m], lanes (a0,b0,c0), (a0,b0,c0+1), (a1,b1,c1), (a1,b1,c1+1)
  int most_chunks = 0;                   // most chunks of one particle (scratch size)
  // --- end of the shape-memory chunk layout ---

  // stability
  double stable_dt_estimate = 0.0; // largest stable substep of the linearisation, with the
                                   // stiffness damping below where it is set [s]
  // solver.stiffness_damping_s: Rayleigh stiffness-proportional damping beta (C = beta K). The
  // elastic forces (shape memory, strain, tet, shell) of each substep are evaluated at x + beta v
  // instead of x, which to first order adds -beta K v (engine/step/stiffness_damping.cpp).
  // It damps a mode of frequency omega at a ratio zeta = beta omega / 2: the wall's fast ringing
  // strongly, the organ-scale motion not at all. 0: off.
  double stiffness_damping = 0.0;  // [s]
  // solver.mass_scaling (compile.cpp scale_inertia_to_substep): inertial mass added so that the
  // file's substep is stable instead of raising the substep count; gravity still acts on `mass`
  // and the damping force c m v is kept (damping rate scaled down by the same factor)
  double added_inertia = 0.0;      // total inertial mass added [kg]
  double largest_inertia_factor = 1.0; // largest m_inertial / m of one particle [-]

  // safety limits checked each step
  double max_speed = 50.0;         // a particle faster than this is a blow-up [m/s]
  double max_excursion = 1.0;      // a particle farther than this from rest is a blow-up [m]

  int particle_count() const { return static_cast<int>(rest_pos.size()); }
  int find_component(const std::string& n) const {
    for (size_t c = 0; c < components.size(); ++c)
      if (components[c].name == n) return static_cast<int>(c);
    return -1;
  }
  // The component named `name`, or where `name` is empty the first whose role is `role`; -1 if none.
  int find_organ(const std::string& name, Role role) const { return name.empty() ? find_role(role) : find_component(name); }
  // The first component with role r, -1 if none.
  int find_role(Role r) const {
    for (size_t c = 0; c < components.size(); ++c)
      if (components[c].role == r) return static_cast<int>(c);
    return -1;
  }
  // Role of tag t (Role::Other where the model has no roles for its tags).
  Role tag_role(int t) const { return t >= 0 && t < static_cast<int>(tag_roles.size()) ? tag_roles[t] : Role::Other; }
};

}  // namespace ps
