// ScenarioSpec mirrors a scenario file, already converted to SI units (files use mm, kPa, ms;
// conversion happens once, in parse_yaml.cpp). It is the editable form: the instructor editor
// changes a ScenarioSpec, compile_scenario() turns it into an immutable Model.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/spec/needle_spec.h"
#include "engine/util/vec.h"

namespace ps {

// Where in the file a value came from, for error messages.
struct SourceLoc {
  std::string file;
  int line = 0;  // 1-based, 0 unknown
};

struct RegionSpec {
  enum Kind { All, Box, Sphere, HalfSpace, Ellipsoid } kind = All;
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();   // Box [m]
  Vec3 center = Vec3::Zero(); double radius = 0; // Sphere [m]
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitZ();  // HalfSpace: keeps (x-point).n >= 0 [m]
  Vec3 radii = Vec3::Zero();       // Ellipsoid: axis-aligned semi-axes about center [m]
  bool contains(const Vec3& x) const;
};

// The material models, in the order of their force stages in a substep.
enum class MaterialModel : uint8_t { Paper, Strain, Tet, Shell };
inline constexpr int kMaterialModelCount = 4;

struct MaterialSpec {
  std::string name;
  std::optional<double> young;     // Young's modulus [Pa]
  std::optional<double> k_e;       // raw shape-memory stiffness override [N/m]
  double density = 1000.0;         // [kg/m^3]
  double damping = 10.0;           // velocity damping rate [1/s]
  bool incompressible = false;     // volume constraint on the component's closed surface
  double k_c = 0.0;                // needle cutting weight [N]
  double k_f = 0.0;                // needle friction weight [N]
  // model: paper (shape memory only, k_e = kappa(h) E h) | strain (shape memory + strain memory,
  // docs/model.md); tet (v2: elements over a Delaunay tetrahedralisation of the particles, "Tet
  // model"); shell (membranes, fill: surface only: co-rotational triangles and dihedral hinges,
  // "Shell model"). poisson applies to strain, tet and shell, k_s to strain, thickness to shell.
  // What each compiles to and which force stage runs it: engine/scenario/material_models.h
  MaterialModel model = MaterialModel::Paper;
  std::optional<double> thickness; // shell wall thickness [m]
  std::optional<double> poisson;   // local Poisson ratio of the strain term [-], in [0, 0.5)
  std::optional<double> k_s;       // raw strain stiffness: shear modulus x spacing [N/m]
  // pressure: implicit (model: tet only): the volumetric term kappa (J_n - 1) of the material's
  // nodes is solved as a compliant constraint per substep (engine/step/tet_pressure.cpp) instead
  // of an explicit force, so it does not set the stable substep (docs/model.md "Implicit pressure")
  bool implicit_pressure = false;
  SourceLoc loc;
};

struct MeshShapeSpec {
  std::string file;                // resolved path
  double unit_scale = 1e-3;        // file units -> m
  Vec3 translate = Vec3::Zero();   // [m]
  Vec3 rotate_deg = Vec3::Zero();  // XYZ Euler [deg]
  Vec3 scale = Vec3::Ones();
};

struct ShapeSpec {
  enum Kind { Box, Cylinder, Mesh } kind = Box;
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();   // Box corners [m]
  Vec3 base = Vec3::Zero();        // Cylinder base centre [m]
  Vec3 axis = Vec3::UnitZ();       // Cylinder axis (unit)
  double radius = 0.0, length = 0.0;  // Cylinder [m]
  MeshShapeSpec mesh;
};

struct ComponentSpec {
  std::string name;
  std::string kind = "elastic";    // elastic | rigid | active
  std::string material;
  std::string role;                // `role:` as written (a word of engine/model/role.h); empty:
                                   // the name's default (default_role), resolved by compile
  ShapeSpec shape;
  double spacing = 0.0;            // particle spacing h [m]
  bool volumetric = true;          // fill: volumetric | surface
  bool kinematic = true;           // rigid: pose changes only by command
  Vec3 fibre = Vec3::UnitZ();      // active: fibre direction
  double active_stress = 0.0;      // active: stress at activation 1 [Pa]
  double activation = 0.0;         // active: initial activation [0,1]
  std::vector<std::string> exclude_inside;  // volumetric: no particles inside (or within 0.45
                                            // spacing of) these components (fat around organs)
  SourceLoc loc;
};

struct ConstraintSpec {
  enum Kind { Fix, Displace, HalfSpace, Force } kind = Fix;
  std::string component;           // empty: all components
  RegionSpec region;
  uint8_t axes = 7;                // Fix/Displace axis mask
  Vec3 by = Vec3::Zero();          // Displace [m] / Force total [N]
  double t0 = 0.0, t1 = 0.0;       // ramp [s]
  SourceLoc loc;
};

struct OverrideSpec {
  std::string component;
  RegionSpec region;
  std::optional<double> young, k_e, k_c, k_f, damping;  // [Pa], [N/m], [N], [N], [1/s]
  SourceLoc loc;
};

struct LinkSpec {
  std::string a, b;
  double distance = 0.0;           // particles closer than this are linked [m]
  SourceLoc loc;
};

// --- probe: and filling: sections (engine/tools/probe/probe.h, engine/tools/filling/filling.h) ---------------
// Probe pose in the rectal frame (entry point E, axis a, anterior n, lateral a x n): pivot
// E + offset, tip-hemisphere centre pivot + insertion * R a, R = tilt(a x n) * yaw(-n) * roll(a).
struct ProbePose {
  double insertion = 0.0;          // pivot to tip-hemisphere centre along the probe axis [m]
  Vec3 offset = Vec3::Zero();      // pivot translation, perpendicular to the rectal axis [m]
  double roll = 0.0;               // about the probe axis [rad]
  double tilt = 0.0;               // toward anterior, about a x n through the pivot [rad]
  double yaw = 0.0;                // toward lateral (a x n), about -n through the pivot [rad]
};

// A scripted probe move: the named fields go from their value at t0 to these at t1 (smoothstep).
struct ProbeMoveSpec {
  double t0 = 0.0, t1 = 0.0;       // [s]
  std::optional<double> insertion; // [m]
  std::optional<Vec3> offset;      // [m]
  std::optional<double> roll, tilt, yaw;  // [rad]
  SourceLoc loc;
};

struct ProbeSpec {
  double radius = 0.010;           // capsule radius [m]
  double length = 0.120;           // modelled shaft: tip-hemisphere centre to back end [m]
  Vec3 entry = Vec3::Zero();       // pivot of tilt/yaw at the anal entry [m]
  Vec3 axis = Vec3::UnitZ();       // rectal axis, insertion direction (unit)
  Vec3 anterior = Vec3::UnitY();   // toward the prostate, made perpendicular to axis (unit)
  ProbePose pose;                  // initial pose
  std::vector<ProbeMoveSpec> moves;
  bool imposed_mode = false;       // contact.mode: imposed (paper §5.4.1 literal) | contact
  std::vector<std::string> contact_components;  // empty: every non-rigid component
  std::string rectum;              // rectum component (start check, imposed-mode source)
  std::string prostate;            // imposed mode: component receiving the displacement
  double couple_distance = 0.0;    // imposed mode: rectum-prostate rest distance [m], 0 = auto
  double max_speed = 0.05;         // commanded translation speed limit [m/s]
  double max_angular_speed = 1.0471975511965976;  // commanded rotation speed limit [rad/s]
  double guide_angle = 0.3490658503988659;        // biopsy guide angle to the probe axis [rad]
  double guide_back = 0.015;       // guide exit point: distance behind the tip centre [m]
  double template_distance = 0.030;  // template plane: distance behind the pivot [m]
  double template_pitch = 0.005;   // hole spacing [m]
  int template_cols = 13, template_rows = 13;
  double template_first_row = 0.010; // row 0 above the probe axis (anterior) [m]
  bool has_guide = false;          // needle_guide: given (drawn on the probe)
  bool has_template = false;       // template: given (grid drawn on the stepper)
  SourceLoc loc, pose_loc;
};

// One filling segment of an organ's target volume (linear in time over [t0, t1]).
struct FillSpec {
  std::string component;
  enum Kind { Rate, Target, Factor } kind = Rate;
  double value = 0.0;              // Rate [m^3/s], Target [m^3], Factor [-] of the rest volume
  double t0 = 0.0, t1 = 0.0;       // [s]
  SourceLoc loc;
};

struct FillingSpec {
  double max_rate = 5e-6;          // physiological limit on |dV/dt| [m^3/s] (5 ml/s)
  std::vector<FillSpec> schedule;
  SourceLoc loc;
};

// Named particle tag (lesion, target, ...): the particles of `component` inside `region`.
struct TagSpec {
  std::string name;
  std::string role;                // `role:` as written; empty: the name's default (default_role)
  std::string component;
  RegionSpec region;
  SourceLoc loc;
};

// Prostate zone tags (engine/anatomy/zones.h) on the particles of one component.
struct ZonesSpec {
  std::string component;
  double peripheral_depth = 8e-3;  // shell thickness of the peripheral / anterior zones [m]
  SourceLoc loc;
};

// Lesions placed per case from a seed (`lesions:`): `count` spheres of `diameter` centred on
// particles of the prostate_zones component drawn (splitmix64 from `seed`, at least a diameter
// apart) among those carrying the zone tag `zone`; their particles get the tags lesion_1,
// lesion_2, ... (MRI-visible targets: cores holding them count as lesion hits). Same seed, same
// case on every machine.
struct LesionsSpec {
  int count = 1;
  uint64_t seed = 1;
  std::string zone = "peripheral";  // a prostate zone tag (engine/anatomy/zones.h)
  double diameter = 10e-3;          // [m]
  SourceLoc loc;
};

struct ScenarioSpec {
  std::string file;                // source path
  std::string name;
  double dt = 1e-3;                // tick [s]
  int substeps = 1;
  double duration = 1.0;           // [s]
  Vec3 gravity = Vec3(0, 0, -9.81);  // [m/s^2]
  // the longest run a scenario (time.duration_s) or a command line (--duration) may ask for [s]
  static constexpr double kMaxDuration = 1e6;
  double rest_kinetic_energy = 1e-7; // --until-rest threshold on kinetic energy [J]
  double rest_hold = 0.05;         // ... held for this long [s]
  // watchdog.leave_margin_mm: how far outside the rest bounding box a particle may go before the
  // watchdog calls it "left the scene" [m] (engine/sim/watchdog.h)
  double leave_margin = 0.05;
  bool linear_redistribution = false;  // solver.redistribution: linear (paper literal) | gradient
  int max_triplets = 0;            // solver.triplets: all (0) | N best-conditioned per particle
  bool mass_scaling = false;       // solver.mass_scaling: scale inertia to the file's substep
  bool multirate = false;          // solver.multirate: tet elements that admit the tick run once per tick
  double multirate_inertia = 1.0;  // solver.multirate_inertia: largest factor of inertial mass that lets a
                                   // particle's elements join the slow group (1: none; compile_time_step.cpp)
  int pressure_iterations = 1;     // solver.pressure_iterations: linearised solves of the implicit
                                   // pressure per substep (materials with pressure: implicit)
  bool sleep = false;              // solver.sleep: tet tissue at rest and in balance sleeps (Model::sleep)
  double sleep_wake_accel = 0.1;   // solver.sleep_wake_m_s2: unbalanced force / mass that wakes it [m/s^2]
  double stiffness_damping = 0.0;  // solver.stiffness_damping_s: Rayleigh beta (Model::stiffness_damping) [s]
  std::vector<MaterialSpec> materials;
  std::vector<ComponentSpec> components;
  std::vector<ConstraintSpec> constraints;
  std::vector<OverrideSpec> overrides;
  std::vector<LinkSpec> links;
  std::vector<TagSpec> tags;                 // tags: named particle regions
  std::optional<ZonesSpec> prostate_zones;   // prostate_zones: zone tags on the prostate
  std::optional<LesionsSpec> lesions;        // lesions: placed from a seed (needs prostate_zones)
  std::optional<ProbeSpec> probe;  // probe: section (engine/tools/probe/probe.h)
  std::optional<FillingSpec> filling;  // filling: section (engine/tools/filling/filling.h)
  NeedleSetSpec needles;           // needles: section (engine/spec/needle_spec.h)
};

}  // namespace ps
