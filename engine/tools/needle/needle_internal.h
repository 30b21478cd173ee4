// Per-needle runtime state shared by the needle's source files (zones, forces, motion, seeds,
// biopsy). Engine-internal: users see NeedleTool (needle.h). Every buffer is sized in the
// constructor; the step functions below never allocate.
#pragma once
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe_geometry.h"

namespace ps {

struct SeedState {
  double depth = 0.0;              // planned depth along the path [m]
  Vec3 planned = Vec3::Zero();     // [m]
  bool deposited = false;
  bool embedded = false;
  double time = 0.0;               // [s]
  Vec3 at = Vec3::Zero();          // deposit position [m]
  Vec3 current = Vec3::Zero();     // carried by the tissue [m]
  AffineAnchor anchor;
};

struct CoreState {
  bool taken = false;
  double time = 0.0;
  std::vector<int> particles;      // capacity kCoreCapacity
  std::vector<int> per_component;  // [components]
  std::vector<int> per_tag;        // [model tags]
  std::vector<double> tumour_pos;  // scratch: axial positions of tumour particles (capacity)
  std::vector<double> tumour_half; // scratch: half spacing of each
  int tumour_particles = 0;
  double tumour_length = 0.0;      // [m]
  int overflow = 0;                // particles beyond capacity (counted, not listed)
  Vec3 tip = Vec3::Zero();         // needle tip and direction when the core was taken [m]
  Vec3 direction = -Vec3::UnitZ();
};
inline constexpr int kCoreCapacity = 2048;
inline constexpr int kMaxGuideCores = 24;   // cores one needle in the guide keeps (a 12-core biopsy + repeats)

struct NeedleTool::Needle {
  NeedleSpec spec;
  int index = 0;
  // geometry
  int node_count = 0;
  double radius = 0.0;             // needle radius [m]
  double Rc = 0.0, Rf = 0.0;             // zone radii [m]
  double halo = 0.0;               // tube margin = largest tissue spacing near the path [m]
  double notch_radius = 0.0;       // [m]
  double node_scale = 1.0;         // friction per node = eq. 6 * node_spacing / 1 mm
  // planned line: eligible particles near it, sorted by rest position along it
  std::vector<int> plan_idx;
  std::vector<double> plan_t;      // [m]
  int seed_counter = 0;
  // kinematics
  Vec3 T = Vec3::Zero();           // tip [m]
  Vec3 V = Vec3::Zero();           // [m/s]
  Vec3 d = -Vec3::UnitZ();         // direction (unit)
  double v_cut = 0.0;              // axial speed low-passed over kCutFilterTime, gates cutting [m/s]
  // command
  bool interactive = false;
  Vec3 cmd_T = Vec3::Zero(), cmd_d = -Vec3::UnitZ(), cmd_V = Vec3::Zero();
  double cmd_speed = 0.0;          // live advance (+) / retract (-) along cmd_d [m/s]
  double cmd_t0 = 0.0;             // time cmd_T holds at; the tip moves at cmd_speed from it [s]
  double hub_roll = 0.0;           // hub rotation about the shaft (shown, no mechanics) [rad]
  bool deposit_request = false;    // live DepositSeed: release the next seed after this substep
  double fire_time = NAN;          // gun fire time [s] (NaN: not fired)
  // tube
  std::vector<int> tracked, next;  // capacity n
  std::vector<uint8_t> mark;       // [n] in tube
  std::vector<uint8_t> entered;    // [components] surface breached (or started inside): 1; the
                                   // watched gland (set_gland) 2 while the tip is out of it again
  // zones
  std::vector<int> zone_idx;       // [node_count * kZoneCapacity]
  std::vector<double> zone_dist;   // [node_count * kZoneCapacity] distance to the node [m]
  std::vector<int> zone_n;         // [node_count]
  std::array<int, kCutCapacity> cut_idx{};
  std::array<double, kCutCapacity> cut_dist{};
  int cut_n = 0;
  // this substep's cutting (needle_forces.cpp): the particles that take it and each one's share
  // (sum 1), and the eq. 5 force at full speed; how much of it acts is solved with the needle's
  // velocity (move_needle). Scratch of one substep: not saved.
  std::array<int, kCutCapacity> cut_share_idx{};
  std::array<double, kCutCapacity> cut_share{};
  int cut_share_n = 0;
  double cut_full = 0.0;                 // [N]
  int breached_now = -1;                 // component whose surface broke this substep, -1: none
  // pressed surface: the entry face of an intact membrane the needle axis crosses behind the
  // tip, and the patch of that membrane's particles around the crossing that shares the load
  int press_n = 0;                       // particles in the patch (0: not pressing)
  std::array<int, 3> press_face{};       // crossed face (particles)
  std::array<int, kPressCapacity> press_idx{};
  std::array<double, kPressCapacity> press_w{};  // kernel weights, sum 1
  double press_a = 0.0;                  // crossing position along d relative to the tip (< 0) [m]
  int press_component = -1;
  std::vector<uint32_t> face_epoch;      // [faces] last substep a face was tested
  std::vector<uint8_t> face_breached;    // [faces] sheet faces this needle has torn through
  int press_face_id = -1;                // index of the crossed face in MembraneFaces
  uint32_t epoch = 0;
  // the lumen of a wall (sheet) the tip started in (transrectal biopsy: the rectum, the needle in
  // the probe's guide). The lumen holds no tissue: until the tip has gone out through the wall,
  // only the pressed patch touches the needle (zones would otherwise reach through the intact
  // wall and cut and rub the tissue beyond it, dragging the wall ahead of the tip); afterwards
  // only the part of the shaft beyond the hole does, and the wall rubs it only at the hole.
  int lumen = -1;                        // sheet component, -1: none
  bool near_urethra = false;             // tip within the urethra's radius (Urethra event given)
  bool in_lumen = false;                 // the tip is inside it
  double exit_a = -1e300;                // the hole's position along d relative to the tip (< 0) [m]
  Vec3 exit_point = Vec3::Zero();        // where the axis crosses the wall at the hole [m]
  // virtual tissue particles
  std::vector<AffineAnchor> anchors;     // [node_count]
  // stability bound of the virtual-particle springs (needle_coupling.cpp): per node, the bound
  // c_a of |dP*/dx_a| for each anchor particle a and their sum, and the stiffness scale <= 1
  std::vector<double> anchor_c;          // [node_count * kAnchorMaxNeighbours]
  std::vector<double> anchor_csum;       // [node_count]
  std::vector<double> stick_scale;       // [node_count] virtual stiffness = stick_stiffness * scale
  std::vector<double> stick_scale_used;  // [node_count] the scale of the previous substep
  std::vector<uint8_t> stuck;            // [node_count] 1 stick, 0 slip
  std::vector<uint8_t> reported;         // [node_count] last reported (255: not yet settled)
  std::vector<int> pending;              // [node_count] substeps the new state has held
  int debounce = 1;                      // substeps a stick/slip change must hold to be reported
  // contact bookkeeping
  bool contacted = false;
  double contact_axial = 0.0;            // T.d at first contact [m]
  double peak_force = 0.0;               // largest axial force since contact / last puncture [N]
  bool bone_touch = false;
  bool clamping = false;
  int phase_blocked = 0;                 // substeps left flagged as blocked
  // in the probe's biopsy guide (spec.guide, needle_guide.cpp): the guide's path this substep and
  // the previous one, the commanded depth beyond its exit (the gun's stroke aside) at cmd_t0, and
  // the cores taken before the last re-arming
  bool guided = false;
  NeedlePath guide_now, guide_prev;
  double h_sub = 0.0;                    // the substep [s] (guide velocity)
  double cmd_depth = 0.0;                // [m]
  double plan_reach = 0.0;               // plan list: particles within this of the planned line [m]
  std::vector<std::pair<double, int>> plan_scratch;  // capacity n
  std::vector<CoreState> cores_done;     // [kMaxGuideCores], the first cores_done_n in use
  int cores_done_n = 0;
  // read-out
  NeedleReadout ro;
  double tick_sum = 0.0;
  int tick_n = 0;
  NeedleZoneStats stats;
  // seeds and core
  std::vector<SeedState> seeds;
  double deepest = -1e300;               // deepest tip position along the planned line so far [m]
  CoreState core;
  std::vector<uint8_t> tumour;           // [components] counts as tumour in a core
  uint64_t tumour_tags = 0;              // tag bits that count as tumour
};

// Where the axis T + t d crosses the triangle with corner A and edges e1 = B - A, e2 = C - A
// (Moller-Trumbore): t is the crossing's axial position relative to T [m]. False when the axis runs
// in the triangle's plane or passes outside it by more than `tol` in barycentric coordinates.
inline bool axis_crosses_triangle(const Vec3& T, const Vec3& d, const Vec3& A, const Vec3& e1, const Vec3& e2, double tol,
                                  double& t) {
  const Vec3 pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (std::abs(det) < 1e-30) return false;
  const double inv = 1.0 / det;
  const Vec3 tv = T - A;
  const double u = tv.dot(pv) * inv;
  const Vec3 qv = tv.cross(e1);
  const double v = d.dot(qv) * inv;
  if (u < -tol || v < -tol || u + v > 1.0 + tol) return false;
  t = e2.dot(qv) * inv;
  return true;
}

// Surfaces of the membrane components (puncture_n > 0) as faces incident to their particles.
struct MembraneFaces {
  std::vector<std::array<int, 3>> faces;   // outward CCW particle triples
  std::vector<int> face_component;         // [faces]
  std::vector<uint8_t> sheet;              // [components] surface-only (wall) component
  std::vector<int> start;                  // [n+1] CSR: faces incident to particle p
  std::vector<int> list;
  double max_puncture = 0.0;               // largest puncture weight [N]
};

// needle_zones.cpp: tube walk and zone membership (cutting, puncture, friction per node)
void update_needle_zones(NeedleTool::Needle& nd, const Model& m, const State& s, const std::vector<double>& puncture_kc,
                         const MembraneFaces& mf, NeedleEventRing& events);
// Per-particle bound on the needle-tissue coupling stiffness (needle_coupling.cpp), shared by
// all needles of the tool: G_q = sum over anchors A holding q of k_A c_A,q C_A / m_q, a
// (block Gershgorin) upper bound on the largest eigenvalue of M^-1 K_needles [1/s^2].
struct CouplingBudget {
  std::vector<double> g;                   // [n] G_q, 0 outside the touched list
  std::vector<int> touched;                // particles with g > 0 (capacity n)
  double peak = 0.0;                       // largest G_q h^2 before scaling, last substep
  double after = 0.0;                      // largest G_q h^2 after scaling (<= kCouplingBudget)
  int softened = 0;                        // nodes whose stiffness was scaled down, last substep
};
// needle_coupling.cpp: (re)builds each node's anchor on its zone (virtual tissue particle), then
// bounds the summed coupling stiffness per particle over every needle (scale per node)
void prepare_needle_anchors(NeedleTool::Needle& nd, const State& s);
void bound_needle_coupling(std::vector<std::unique_ptr<NeedleTool::Needle>>& needles, const Model& m,
                           double dt, CouplingBudget& budget);

// needle_forces.cpp: Algorithm 2 per node: puncture contact, virtual elastic force, stick/slip
// onto the particles; returns their reaction on the needle [N]. The cutting zone and its full
// eq. 5 force are prepared (cut_share, cut_full), not applied: the part that acts depends on the
// needle's new velocity (move_needle). (h: the substep [s])
Vec3 apply_needle_tissue_forces(NeedleTool::Needle& nd, const Model& m, State& s, const std::vector<double>& puncture_kc,
                                const MembraneFaces& mf, double h, NeedleEventRing& events);
// needle_forces.cpp: the cutting force `cut` [N] onto the prepared zone, and the substep's
// read-out (tissue force = `f_other` + cutting, axial force, peak) and puncture event
void apply_needle_cutting(NeedleTool::Needle& nd, State& s, const Vec3& f_other, double cut, NeedleEventRing& events);
// needle_setup.cpp: the steps of NeedleTool's constructor
std::vector<double> needle_puncture_weights(const Model& m, const NeedleSetSpec& set);  // [components] N; InputError
std::unique_ptr<MembraneFaces> needle_membrane_faces(const Model& m, const std::vector<double>& puncture_kc);
struct TissueExtent {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // box of the tissue particles at rest [m]
  double h_global = 0.0;                      // largest tissue spacing [m]
};
TissueExtent tissue_extent(const Model& m);
void size_needle_buffers(NeedleTool::Needle& nd, const Model& m, const MembraneFaces& mf);
void resolve_tumour(NeedleTool::Needle& nd, const Model& m);  // InputError for an unknown tumour name
void check_needle_stiffness(const NeedleSpec& spec, const Model& m, double h_sub, double m_min, std::vector<std::string>& warnings);
// The needle's plan; m_min: the lightest planned particle so far over every needle [kg] (updated)
std::unique_ptr<NeedleTool::Needle> plan_needle(const Model& m, const NeedleSpec& spec, int index, const TissueExtent& ext,
                                                const MembraneFaces& mf, const std::vector<double>& puncture_kc, double& m_min,
                                                std::vector<std::string>& warnings);
// needle_motion.cpp: commanded pose at time t
void needle_command(const NeedleTool::Needle& nd, double t, Vec3& tip, Vec3& dir, Vec3& vel);
// needle_motion.cpp: computeNeedleMovement + adjustIntensityNeedleVelocity + bone stop; the
// cutting force solved with the new velocity and applied (apply_needle_cutting). f_tissue: the
// other tissue forces on the needle [N]
void move_needle(NeedleTool::Needle& nd, const Model& m, State& s, const Vec3& f_tissue, double dt, const BoneContact* bone,
                 NeedleEventRing& events);
// needle_motion.cpp: the cutting force [N] when the needle's axial speed after the substep is
// u = u0 - beta * C (u0: its speed without cutting [m/s]; beta = h / effective mass [s/kg]) and C
// = c_full * clamp(v_cut' / v_ramp, 0, 1) with the gate's filtered speed v_cut' = (1 - a) v_cut
// + a u: the root of u + beta C(u) = u0, unique as C does not decrease with u
double implicit_cutting_force(double c_full, double u0, double beta, double v_cut, double a, double v_ramp);
// needle_guide.cpp: a needle in the probe's guide. Before the zones of a substep: the guide at the
// probe's pose now, and the planned-line list rebuilt around it once it has moved by more than a
// quarter of plan_margin. After the step: a fired needle withdrawn into the guide with its core
// taken is re-armed (its core kept). Back in the lumen: it has entered nothing and touched nothing.
void follow_guide(NeedleTool::Needle& nd, const Model& m, const State& s, const NeedlePath& guide);
void rearm_in_guide(NeedleTool::Needle& nd, double t);
void reset_contact_in_lumen(NeedleTool::Needle& nd, const MembraneFaces& mf);
// guided needle: commanded tip depth beyond the guide's exit at time t, the gun's stroke included [m]
double guide_depth(const NeedleTool::Needle& nd, double t);
// seeds.cpp / biopsy.cpp (after the step)
void update_seeds(NeedleTool::Needle& nd, const Model& m, const State& s, NeedleEventRing& events);
double gun_stroke(const NeedleTool::Needle& nd, double t);
double gun_stroke_rate(const NeedleTool::Needle& nd, double t);
void update_biopsy(NeedleTool::Needle& nd, const Model& m, const State& s, NeedleEventRing& events);

inline Vec3 needle_node(const NeedleTool::Needle& nd, int j) { return nd.T - (j * nd.spec.node_spacing) * nd.d; }
inline double plan_depth(const NeedleTool::Needle& nd) { return (nd.T - nd.spec.start).dot(nd.spec.direction); }
inline double insertion_depth(const NeedleTool::Needle& nd) { return nd.contacted ? nd.T.dot(nd.d) - nd.contact_axial : 0.0; }

inline void push_event(NeedleEventRing& ev, const NeedleTool::Needle& nd, NeedleEventKind k, double t, const Vec3& pos,
                       int component = -1, int node = -1, double value = 0.0) {
  NeedleEvent e;
  e.kind = k;
  e.needle = nd.index;
  e.time = t;
  e.position = pos;
  e.depth = insertion_depth(nd);
  e.force = nd.ro.axial_force;
  e.component = component;
  e.node = node;
  e.value = value;
  ev.push(e);
}

}  // namespace ps
