// Rigid needle insertion (paper §4.2, Algorithm 2) as an engine Tool: every needle of a scenario
// (one brachytherapy template holds 20+) in one tool, one event ring.
//
// Model. A needle is a line of nodes (spacing s) from the tip back to the hub, moved as one rigid
// body: its tip T (velocity V) follows a commanded pose (script or interactive command) through
// a spring-damper coupling, integrated implicitly, and the tissue reaction is added explicitly:
//   m dV/dt = F_coupling + F_tissue          (computeNeedleMovement)
// F_tissue is the force feedback read-out. Its direction d is commanded (kinematic).
// Forces between needle and tissue are applied directly on particles; no collision, no remesh.
//
// Zones of interest, per needle (radii default to 1.0 x the largest tissue spacing near the
// planned path so that a zone inside tissue is never empty between lattice planes):
//  * cutting zone: particles within cutting_radius of the tip and not behind the tip plane;
//  * puncture zone (before a component's surface is breached): the faces of its surface around
//    the tracked surface particles, tested against the needle axis;
//  * friction zone of node j: particles behind the tip plane within friction_radius of the node
//    (at most kZoneCapacity nearest).
// All live in a tracked tube around the shaft. After the first contact the tube is rebuilt each
// substep by walking the CSR neighbours of the particles already in it (a flood fill limited to
// the tube), so its cost depends on the inserted length, not on the scene; new components not
// linked by neighbours are found through a precomputed list of particles near the planned line,
// sorted along it, of which only the slice around the tip is examined (`stats()` counts).
//
// Forces (tissue side; the opposite acts on the needle):
//  * puncture (pre-breach contact): a membrane is a surface, not a set of points, so the tip
//    presses the entry face (outward normal against d) that the needle axis crosses behind the
//    tip, so it cannot slip between particles: P = press_stiffness * (depth of the tip beyond
//    the crossing X), along d. The load is shared by the membrane particles of the puncture zone
//    (the cutting zone before entry, paper §4.2.1): those within R = max(cutting_radius, longest
//    edge of the crossed face) of X, with weights 1 - (r/R)^2. (Loading only the face's three
//    particles made a spike so deep and narrow that the lattice under it buckled at ~15 mm.)
//    The contact is critically damped on the approach speed of tip and patch (a sharp tip
//    indents, it does not bounce: P += 2 sqrt(k M) (V - v_patch) . d, M the patch's effective
//    mass), so a fast tip reaches the threshold after less deflection (docs/needle.md).
//    The surface deflects before puncture and is breached, in the substep where P reaches the
//    same weighted average of the puncture weights (`puncture_n`, eq. 5): event (value: P at
//    rupture), and the component counts as entered, so its particles are cut and rub from then on. Before that, an intact
//    membrane's particles take no cutting or friction (the needle is outside it). A needle that
//    starts inside a volume has entered it. Walls modelled as surfaces (fill: surface: rectum,
//    bladder) are sheets: pressed from either side (transrectal biopsy leaves the lumen through
//    the wall), torn one hole at a time (a far wall is punctured again), never cut; their
//    particles outside the pressed patch rub the shaft. A needle that starts in a wall's lumen
//    (transrectal: in the probe's guide) touches nothing but the patch it presses until it is
//    through; then only its part beyond the hole meets the tissue beyond the wall, and the wall
//    rubs it at the hole only (the lumen and the guide hold no tissue; zones one spacing wide
//    would otherwise reach through the intact wall, cut and rub the fat beyond it and drag the
//    wall ahead of the tip: it tented 7 mm and broke at 4.2 N total against its 1.5 N).
//  * cutting (eq. 5): C = sum k_c^i/d_i / sum 1/d_i over the cutting zone of entered components,
//    particle i receives k_c^i (1/d_i) / sum 1/d_j along d. Applied only while the needle moves
//    forward (ramped in over cut_velocity, on the axial speed low-passed over kCutFilterTime):
//    no cutting while retracting or at rest. The ramp is solved with the needle's new velocity
//    (move_needle, implicit like the coupling): on it the gate is a damper of k_c / cut_velocity,
//    too stiff for an explicit step of the light needle. When the tip
//    sits between particle layers and the cutting zone is momentarily empty, the tip node's
//    friction-zone particles take the cutting force, so the force does not flicker with the
//    lattice. Distances below the needle radius count as the needle radius.
//  * friction (eq. 6) with stick/slip through virtual tissue particles: node j carries an anchor
//    (AffineAnchor, affine weights of the node w.r.t. its zone particles, linear in their
//    positions: where the paper uses its discrete coordinates, needle_anchor.h says why); the
//    virtual elastic force F_v = stick_stiffness (P* - X_j). Its axial part is the friction: while
//    |F_v . d| < static threshold (static_ratio * F) the node sticks and F_v couples needle and
//    tissue (redistributed to the anchor particles, paper §3.2); beyond it the node slips and the
//    anchor slides along the shaft so the axial force stays at the kinetic value F (eq. 6 times
//    s / 1 mm: k_f is read as friction per millimetre of shaft, so the total does not depend on
//    the node spacing). The lateral part of F_v is kept in both states: it is the rigid shaft's
//    normal contact that keeps tissue from flowing through it (a deliberate addition to the
//    paper, whose slide state applies the axial friction only). Slip returns to stick when the
//    axial spring force falls below F (motion stops or reverses).
// Stability: the virtual-particle springs are explicit; where the summed stiffness of all the
// nodes (of all needles) holding a particle would exceed the explicit limit of the substep,
// those nodes' springs are softened for that substep (needle_coupling.cpp, kCouplingBudget).
// Safety: the coupling force is clamped at max_force and the speed at max_speed (event, and
// State::clamp_count); every tissue force is bounded by a threshold (k_c, puncture, friction), so
// an absurd command cannot blow the tissue up.
// Bone: rigid components are never cut; the tip is stopped on their surface (FCL, see
// bone_contact.h) with an event saying where.
// Nothing in the hooks allocates, logs or touches files; all buffers are sized at construction.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "engine/step/simulation.h"
#include "engine/tools/needle/needle_anchor.h"
#include "engine/tools/needle/needle_events.h"
#include "engine/spec/needle_spec.h"

namespace ps {

class BoneContact;
struct CouplingBudget;
struct MembraneFaces;

inline constexpr double kCutFilterTime = 5e-3;  // low-pass of the speed that gates cutting [s]
inline constexpr int kZoneCapacity = 12;     // particles kept per friction zone (nearest)
inline constexpr int kCutCapacity = 32;      // particles in the cutting zone
inline constexpr int kPressCapacity = 48;    // membrane particles sharing the puncture load
// Bound on the virtual-particle springs of all needles together, as a (Gershgorin, so
// pessimistic) bound of lambda_max(M^-1 K) h^2 of the coupling alone (needle_coupling.cpp):
// half of the explicit limit 4 of symplectic Euler. It ignores the tissue's own stiffness at the
// particle, small where needles gather (3 kPa fat near the capsule: lambda h^2 ~ 1e-3).
inline constexpr double kCouplingBudget = 2.0;

enum class NeedlePhase : uint8_t { Outside, Pressing, Inserted, Blocked };

// Read-out of one needle (force feedback and what a UI shows). Forces are on the needle [N].
struct NeedleReadout {
  Vec3 tip = Vec3::Zero();              // [m]
  Vec3 direction = -Vec3::UnitZ();
  Vec3 velocity = Vec3::Zero();         // [m/s]
  Vec3 command_tip = Vec3::Zero();      // [m]
  double plan_depth = 0.0;              // tip depth along the planned line from the start [m]
  double depth = 0.0;                   // insertion depth since first contact [m] (0 before)
  bool contacted = false;
  Vec3 tissue_force = Vec3::Zero();     // tissue reaction on the needle, last substep [N]
  Vec3 coupling_force = Vec3::Zero();   // coupling force on the needle, last substep [N]
  double axial_force = 0.0;             // -tissue_force . d: resistance to insertion [N]
  double axial_force_tick = 0.0;        // same, averaged over the last complete tick [N]
  double press_force = 0.0;             // puncture contact part [N]
  double cutting_force = 0.0;           // cutting part [N]
  double friction_force = 0.0;          // axial friction part (sum over nodes) [N]
  int engaged_nodes = 0;                // nodes whose friction zone holds tissue
  int stuck_nodes = 0;                  // of which sticking
  NeedlePhase phase = NeedlePhase::Outside;
};

// Zone bookkeeping cost of the last substep, per needle (scene-size independence tests).
struct NeedleZoneStats {
  int tracked = 0;                      // particles in the tube
  int visited = 0;                      // particles whose position was tested this substep
  int plan_checked = 0;                 // of which from the planned-line slice
};

// The stability bound of the needle-tissue coupling in the last substep (needle_coupling.cpp).
struct NeedleCouplingStats {
  double bound = 0.0;                   // max_q G_q h^2 of the virtual springs as specified
  double bound_applied = 0.0;           // same after the per-node scaling (<= kCouplingBudget)
  int softened_nodes = 0;               // nodes (all needles) whose spring was scaled down
  double bound_max = 0.0;               // largest `bound` since the start
  int64_t softened_substeps = 0;        // substeps in which the scaling acted
};

struct SeedReport {
  int needle = -1, index = -1;
  bool deposited = false;
  bool embedded = false;                // held by tissue particles (false: deposited in air)
  double time = 0.0;                    // deposit time [s]
  Vec3 planned = Vec3::Zero();          // start + depth * direction [m]
  Vec3 deposited_at = Vec3::Zero();     // [m]
  Vec3 current = Vec3::Zero();          // carried by the tissue [m]
  double error = 0.0;                   // |current - planned| [m]
};

struct CoreReport {
  int needle = -1;
  bool taken = false;
  double time = 0.0;                    // [s]
  std::vector<int> particles;           // in the notch
  std::vector<std::pair<std::string, int>> per_component;  // component (organ) -> particle count
  std::vector<std::pair<std::string, int>> per_tag;        // tag (zone, lesion) -> particle count
  int tumour_particles = 0;
  double tumour_length = 0.0;           // length of the core occupied by tumour [m]
  double notch_length = 0.0;            // [m]
  Vec3 notch_centre = Vec3::Zero();     // where the notch's centre was when the core was taken [m]
  Vec3 direction = -Vec3::UnitZ();      // the needle's direction then
};

struct ToolKind;  // engine/tools/tool_kind.h

class NeedleTool : public Tool {
 public:
  // its entry in the instrument registry (needle_kind.cpp, engine/tools/tool_kind.h)
  static const ToolKind& kind();
  // Validates the needles against the model (InputError naming the needle field): path that
  // never comes near the scene, unknown components in puncture_n, unknown tumour components/tags.
  NeedleTool(std::shared_ptr<const Model> model, const NeedleSetSpec& spec);
  ~NeedleTool() override;

  const char* name() const override { return "needles"; }
  void forces(const Model& m, State& s, double dt) override;
  void after_step(const Model& m, State& s, double dt) override;
  // shaft, tip, depth marks every 10 mm, hub, seeds, force arrow (needle_draw.cpp)
  void draw(DrawSink& out, const Model& m, const State& s) const override;
  // live use (needle_live.cpp): NeedleAim/Advance/Rotate/Release, FireGun, DepositSeed,
  // SelectNeedle, SelectHole (needs attach_probe)
  bool apply(const Command& c, const Model& m, const State& s, CommandRefusal& why) override;
  bool accepts(CommandKind k) const override;
  int find_item(const char* name) const override { return find(name); }
  void serialize(StateIO& io) override;
  void readout(ToolReadout& r, const Model& m, const State& s) const override;
  int64_t events_since(int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out, size_t max_size) const override;
  // The probe whose template and guide SelectHole aims along (build_scene attaches it).
  // A needle in the guide (NeedleSpec::guide) follows this probe's guide from now on.
  void attach_probe(const class ProbeTool* probe);
  bool guided(int i) const;                // rides in the probe's biopsy guide
  // The urethra's centre line at rest [m], carried by the nearest particle of a component whose
  // role is prostate, and its radius [m]: a tip that comes within the radius gives an Urethra
  // event (needle_structures.cpp). Before the first step (the kind's make sets it from Model::urethra).
  void set_urethra(const std::vector<Vec3>& centre_line, double radius);
  // The gland whose capsule a tip may leave again (GlandExit event, needle_structures.cpp): a
  // component with a punctured surface (puncture_n); -1 or one without: not watched.
  void set_gland(int component);
  int active() const { return active_; }   // the selected needle (SelectNeedle), 0 at start
  double hub_roll(int i) const;            // NeedleRotate [rad]

  int count() const { return static_cast<int>(needles_.size()); }
  int find(const std::string& name) const;
  const NeedleSpec& spec(int i) const;
  const NeedleReadout& readout(int i) const;
  const NeedleZoneStats& stats(int i) const;
  const NeedleCouplingStats& coupling() const { return coupling_stats_; }
  // Interactive command (between ticks): from now on the needle follows this tip pose and
  // velocity instead of its script. Direction must be non-zero (normalised here).
  void command(int i, const Vec3& tip, const Vec3& direction, const Vec3& velocity = Vec3::Zero());
  void release_command(int i);  // back to the script
  // Fire the biopsy gun now (interactive); the script's gun.fire_s does it automatically.
  void fire(int i, double now);

  const NeedleEventRing& events() const { return events_; }
  std::vector<SeedReport> seeds() const;
  CoreReport core(int i) const;             // the last core (taken or not)
  std::vector<CoreReport> cores(int i) const;  // every core taken, oldest first (a needle in the guide takes several)
  // Nodes of needle i at the current pose [m] (rendering, tests).
  std::vector<Vec3> nodes(int i) const;
  // Particles in the friction zone of node j of needle i (tests, visualisation).
  std::vector<int> zone_particles(int i, int node) const;
  std::vector<int> cutting_particles(int i) const;
  bool node_stuck(int i, int node) const;
  bool node_anchor_rotational(int i, int node) const;
  bool component_entered(int i, int component) const;
  const std::vector<std::string>& warnings() const { return warnings_; }

  struct Needle;  // per-needle runtime state (needle.cpp)

 private:
  std::shared_ptr<const Model> model_;
  std::vector<std::unique_ptr<Needle>> needles_;
  std::vector<double> puncture_kc_;     // [components] surface puncture weight [N], 0: none
  std::unique_ptr<MembraneFaces> membranes_;
  NeedleEventRing events_;
  std::unique_ptr<BoneContact> bone_;
  std::unique_ptr<CouplingBudget> budget_;
  NeedleCouplingStats coupling_stats_;
  std::vector<std::string> warnings_;
  int active_ = 0;
  const ProbeTool* probe_ = nullptr;
  // urethra centre line: rest points, the particle carrying each, scratch of the current line
  std::vector<Vec3> urethra_rest_;
  std::vector<int> urethra_carrier_;
  std::vector<Vec3> urethra_now_;
  double urethra_radius_ = 0.0;
  void check_urethra(const Model& m, const State& s);
  int gland_ = -1;                      // component watched for GlandExit, -1: none
  std::array<double, 16> gland_cross_t_{};  // scratch: the shaft's crossings of its surface [m]
  void check_gland_exit(const Model& m, State& s);
};

// Builds the tool for the `needles:` section of a scenario (nullptr when it has no needle).
std::unique_ptr<NeedleTool> make_needle_tool(std::shared_ptr<const Model> model, const NeedleSetSpec& spec);

}  // namespace ps
