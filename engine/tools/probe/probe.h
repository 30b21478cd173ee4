// Endorectal ultrasound probe (paper §4.1, §5.4.1; issue 5): a rigid kinematic capsule whose pose
// is commanded (scripted moves from the scenario, live move_to() between ticks), pushing tissue
// by displacement boundary conditions.
//
// Contact modes (probe.contact.mode):
//  - contact (DEFAULT): every substep, in the Tool::constraints hook, each particle of the
//    contact components that lies inside the capsule is projected along the capsule normal onto
//    its surface (frictionless displacement boundary condition) and marked State::contact = 7 so
//    the volume projection leaves it alone; its velocity follows through the engine's velocity
//    adjust. The prostate then moves through whatever tissue lies between it and the probe
//    (rectal wall, fat), so its motion depends on that tissue's stiffness, and the guarantee
//    below holds for every tissue particle. That is why it is the default.
//  - imposed (paper §5.4.1 literally: "displacements are imposed to the prostate particles
//    directly in contact with the rectum particles in collision with the probe"): contact as
//    above, plus every prostate particle within couple_distance (at rest) of a rectum particle
//    that the probe holds this substep rides rigidly on the probe (kept at the probe-frame
//    position it had when the coupling began; contact = 7) until none of its rectum particles
//    touches the probe any more. Its displacement is thus imposed by the probe's motion. Two
//    other readings were tried and blew the scene up: imposing the rectum particles' own
//    displacement (absolute rest + u_c jumps by millimetres when the contact set changes;
//    incremental x_prev + du_c feeds back, because the pinned prostate particle's shape-memory
//    reaction pushes the rectum particle it follows; both passed the 50 m/s blow-up limit within
//    0.1 s of a 6 mm push in the test scene). This mode bypasses the tissue in between (a
//    stiffer, more local response), needs the prostate to touch the rectum at rest, and is kept
//    as the paper's reference.
//
// Penetration: the aim is that after every substep no movable particle of the contact components
// is inside the probe by more than kProbePenetrationTolerance (0.1 mm); max_penetration() measures
// it every substep and the tests check it after every tick. The volume projection runs after the
// tool and may push non-contact vertices of a constrained surface back into the probe; when a
// contact component shares a vertex with a constrained surface and such a vertex is within the
// probe's 1 mm query margin this substep (in imposed mode, on every substep: its coupled targets
// ride on the probe wherever they are), constraints() alternates project_volumes() and
// the contact projection (at most kProbeVolumeIterations times) until the corrections are below
// 1 um, and the engine's own volume stage then only corrects round-off. With no constrained vertex
// that near, the volume stage cannot push one into the probe (it moves vertices by far less than
// the margin per substep), so the alternation is skipped and the volume stage does the projection
// (measured: 1.7e-18 m with an emptying rectum closing on the probe, 1.3e-5 m without the
// alternation). It is not a proof: if the alternation runs out with larger corrections, the
// residual shows in max_penetration(). Particles held by the scene (fixed, imposed, rigid / bone)
// are never moved by the probe; if the probe is driven into them they are counted in
// blocked_count() (reported, not a fault). Contact is against particles only: a membrane
// triangle between two particles resting on the probe may sag into it by about h^2 / (8 r)
// (0.3 mm for h = 5 mm, r = 10 mm).
//
// Broad phase (which particles to test): an axis-aligned box around the capsule over every
// candidate particle (DEFAULT, ProbeBroadPhase::Box), or FCL (engine/tools/fcl_surface.h): one FCL
// AABB tree over the surface triangles of every component the probe may touch (the rectal wall
// first, then the prostate, fat, bladder and bone surfaces when they are in the contact set),
// refitted to the particles' positions and queried against a capsule kProbeQueryMargin wider than
// the probe, once per substep at the start of constraints(); the vertices of the triangles with a
// corner inside that capsule are the candidates of that substep, so the query misses no surface
// particle; particles on no such surface (interior particles of volumetric components) are
// candidates when inside the capsule's bounding box. The exact projection below then acts on the
// candidates only, so the 0.1 mm guarantee depends on neither broad phase. The margin (1 mm)
// covers what the volume alternation and the engine's volume stage move particles after the query
// (measured below 1 um), and after_step() reads the penetration over the same candidates. Both
// give bit-identical states (tested). The box is the default because it costs less: one capsule
// against a few thousand particles is not a case a tree pays for, since the tree has to be
// refitted over every triangle every substep (bench/probe_bench.cpp, docs/performance.md: 12 us
// against 37 us per substep on the biopsy scene). No allocation per query in either.
//
// Reaction force (force feedback read-out): a contact correction dx_p of a particle of mass m_p
// over a substep dt stands for a force m_p dx_p / dt^2 applied by the probe (in quasi-static
// contact it equals the elastic force pressing the particle on the probe). The tissue's force on
// the probe is minus the sum, averaged over the substeps of the last tick; the torque is about
// the pivot.
//
// Commanded motion: each scripted move and each move_to() takes the named pose fields from their
// value when it starts to the target, along a smoothstep 3s^2 - 2s^3 (zero velocity at both
// ends: a hand-held probe starts and stops smoothly and the tissue is not kicked). A move that
// starts takes over from the one running (which stops where it is). Moves faster than
// max_speed (translation, |d insertion| + |d offset|) or max_angular_speed (|d roll| + |d tilt|
// + |d yaw|) at their peak (1.5x the mean) are lengthened to the limit and reported.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "engine/step/simulation.h"
#include "engine/tools/fcl_surface.h"
#include "engine/tools/probe/probe_geometry.h"
#include "engine/tools/tool_reports.h"

namespace ps {

inline constexpr double kProbePenetrationTolerance = 1e-4;  // [m] guaranteed after every substep
inline constexpr int kProbeVolumeIterations = 4;            // contact <-> volume alternations
inline constexpr double kProbeMaxTiltRad = 0.7853981633974483;  // |tilt|, |yaw| <= 45 deg
inline constexpr double kProbeQueryMargin = 1e-3;           // [m] FCL query: probe radius + this

enum class ProbeBroadPhase : uint8_t {
  Fcl,   // FCL AABB tree over the contact surfaces, refitted and queried every substep
  Box,   // default: every candidate, axis-aligned box around the capsule
};

struct ToolKind;  // engine/tools/tool_kind.h

class ProbeTool final : public Tool {
 public:
  // its entry in the instrument registry (probe_kind.cpp, engine/tools/tool_kind.h)
  static const ToolKind& kind();
  // Checks the spec against the model and throws InputError (file:line:field) when a named
  // component is missing, the start pose is outside the rectum (the component named
  // contact.rectum, else the first whose role is rectum, if any), overlaps a contact component by more than
  // the tolerance, or lies inside a rigid component (bone).
  ProbeTool(const ProbeSpec& spec, const Model& model);

  const char* name() const override { return "probe"; }
  void boundary_conditions(const Model& m, State& s, double dt) override;
  void constraints(const Model& m, State& s, double dt) override;
  void after_step(const Model& m, State& s, double dt) override;
  // probe body, biopsy guide and its planned path, template grid, force arrow (probe_draw.cpp)
  void draw(DrawSink& out, const Model& m, const State& s) const override;
  // live use (probe_live.cpp): ProbeMove; every mutable field walked by serialize()
  bool apply(const Command& c, const Model& m, const State& s, CommandRefusal& why) override;
  bool accepts(CommandKind k) const override { return k == CommandKind::ProbeMove; }
  void serialize(StateIO& io) override;
  void readout(ToolReadout& r, const Model& m, const State& s) const override;
  // the lengthened moves since `cursor` as snapshot events (kSnapshotEventAdjusted)
  int64_t events_since(int64_t cursor, int tool_index, std::vector<SnapshotEvent>& out, size_t max_size) const override;

  // Broad phase used from the next substep on (default Box). Between ticks.
  void set_broad_phase(ProbeBroadPhase b) { broad_ = fcl_ ? b : ProbeBroadPhase::Box; }
  ProbeBroadPhase broad_phase() const { return broad_; }
  int fcl_triangle_count() const { return fcl_ ? static_cast<int>(fcl_->faces().size()) : 0; }
  int near_count() const { return static_cast<int>(near_.size()); }  // candidates tested last substep

  // --- commands (between ticks, never during a step; the physics thread only: from another
  // thread push a Command through engine/realtime/command_queue.h, applied by
  // engine/realtime/command_apply.h) ---
  // Moves every pose field to `target` over `duration` [s] from the end of the last substep.
  // Returns the duration used (lengthened to the speed limits, then reported). Throws
  // InputError (field "probe.move_to") for a non-finite target, a tilt/yaw beyond 45 degrees or
  // a negative duration.
  double move_to(const ProbePose& target, double duration);

  // --- read-outs ---
  const ProbePose& pose() const { return pose_; }          // commanded, end of last substep
  const ProbeFrame& frame() const { return frame_; }
  const RectalFrame& rectal() const { return rectal_; }
  const ProbeSpec& spec() const { return spec_; }
  Vec3 reaction_force() const { return force_; }           // tissue on probe, tick mean [N]
  Vec3 reaction_torque() const { return torque_; }         // about the pivot, tick mean [N m]
  int contact_count() const { return contacts_; }          // particles corrected last substep
  int imposed_count() const { return imposed_; }           // imposed mode: targets last substep
  double max_penetration() const { return penetration_; }  // movable particles, last substep [m]
  double max_penetration_seen() const { return penetration_seen_; }  // whole run [m]
  int blocked_count() const { return blocked_; }           // held particles inside, last substep
  int64_t blocked_substeps() const { return blocked_substeps_; }
  // substeps on which constraints() alternated with the volume projection, since construction (a
  // diagnostic of this object, not part of the saved state)
  int64_t volume_alternations() const { return volume_alternations_; }
  // Moves lengthened to the speed limits (scripted and live), as records: a live command writes
  // one on the physics thread without allocating (tool_reports.h).
  const ToolReportRing& report_ring() const { return reports_; }
  // The records still held as sentences, oldest first (reader side: allocates), e.g.
  // "t=0.1 s: probe command lengthened from 0.001 s to 0.12 s to respect the speed limits
  // (100 mm/s, 90 deg/s)". A first line says how many older ones were dropped.
  std::vector<std::string> reports() const;
  // One record as text into out[n] (NUL-terminated, truncated to fit; no allocation). brief: no
  // time or file prefix, for SnapshotEvent::text.
  void describe(const ToolReport& r, char* out, size_t n, bool brief = false) const;
  // Why a live move would be refused (a fixed message), nullptr when it is acceptable.
  static const char* check_move(const ProbePose& target, double duration);

  // needle paths fixed to the probe at the current commanded pose
  NeedlePath biopsy_guide() const { return biopsy_guide_path(spec_, frame_); }
  NeedlePath template_hole(int col, int row) const { return template_hole_path(spec_, rectal_, pose_, col, row); }

 private:
  struct Move {
    double t0 = 0.0, t1 = 0.0;     // [s]
    ProbePose from, to;
  };
  // construction steps (probe.cpp); InputError naming the probe's field
  std::vector<uint8_t> contact_set(const Model& m, int& rectum, int& prostate) const;
  ProbeFrame check_start_pose(const Model& m, const std::vector<uint8_t>& in_set, int rectum) const;
  void lengthen_scripted_moves();
  void collect_candidates(const Model& m, const std::vector<uint8_t>& in_set, const std::vector<uint8_t>& on_constrained);
  void build_broad_phase(const Model& m);
  void couple_imposed(const Model& m, int rectum, int prostate, const std::vector<uint8_t>& on_constrained);
  static ProbePose evaluate(const Move& mv, double t);
  double min_duration(const ProbePose& a, const ProbePose& b) const;  // speed limits [s]
  void advance_to(double t);
  void find_candidates(const State& s);                               // fills near_
  bool constrained_vertex_near(const State& s) const;  // a near_ vertex of a constrained surface within the query margin
  double contact_pass(const Model& m, State& s, double inv_dt2);  // returns max correction [m]
  void imposed_pass(const Model& m, State& s, double inv_dt2);
  void add_reaction(const Vec3& x_new, const Vec3& dx, double mass, double inv_dt2);

  ProbeSpec spec_;
  RectalFrame rectal_;
  // commanded motion
  std::vector<ProbeMoveSpec> script_;  // sorted by t0, durations already limited
  size_t next_ = 0;
  Move active_;
  double now_ = 0.0;               // time of pose_ [s]
  ProbePose pose_;
  ProbeFrame frame_;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();  // capsule bounding box this substep [m]
  // contact set (fixed at construction)
  std::vector<int> cand_;          // candidate particles
  std::vector<uint8_t> movable_;   // [cand] 0: held by the scene (fixed, imposed, rigid)
  std::vector<uint8_t> hit_;       // [cand] corrected this substep
  bool volume_coupled_ = false;    // a candidate or target is on a volume-constrained surface
  std::vector<uint8_t> cand_constrained_;  // [cand] on a volume-constrained surface
  // broad phase
  ProbeBroadPhase broad_ = ProbeBroadPhase::Box;
  std::unique_ptr<FclSurfaceContact> fcl_;  // null when no candidate lies on a surface
  std::vector<int> cand_of_;       // [particle] candidate index, -1 if none
  std::vector<int> loose_;         // candidates on no surface of the BVH (always tested)
  std::vector<int> near_;          // candidates tested this substep (capacity: all)
  std::vector<uint8_t> near_mark_; // [cand] scratch: in near_
  // imposed mode: candidate -> coupled target slots (CSR), state per slot
  std::vector<int> couple_start_;  // [cand + 1]
  std::vector<int> couple_slot_;
  std::vector<int> target_;        // [slots] particle
  std::vector<Vec3> local_;        // [slots] position in the probe frame (tip, rot) [m]
  std::vector<uint8_t> coupled_;   // [slots] riding on the probe
  std::vector<uint8_t> touched_;   // [slots] scratch: coupled to a held rectum particle
  // read-outs
  Vec3 force_acc_ = Vec3::Zero(), torque_acc_ = Vec3::Zero();
  Vec3 force_ = Vec3::Zero(), torque_ = Vec3::Zero();
  int substeps_acc_ = 0;
  int contacts_ = 0, imposed_ = 0, blocked_ = 0;
  int64_t blocked_substeps_ = 0;
  int64_t volume_alternations_ = 0;
  double penetration_ = 0.0, penetration_seen_ = 0.0;
  ToolReportRing reports_;
};

// The pose a timeline's probe entries have commanded so far (a probe entry's missing fields keep
// it): the scenario's start pose before the first (probe_kind.cpp).
struct CommandedPose {
  bool set = false;
  ProbePose pose;
};
class TimelineMemory;
ProbePose commanded_probe_pose(const TimelineMemory& memory, const ScenarioSpec& spec);

// The probe of a scenario (nullptr when it has no probe: section).
std::unique_ptr<ProbeTool> make_probe_tool(const ScenarioSpec& spec, const Model& model);

}  // namespace ps
