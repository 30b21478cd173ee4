// Adapters that fill the ultrasound inputs (scene.h) from the simulation, so the app, the
// renderer's panels and the CLI call the image generator the same way:
//  - probe_view(): the ProbeView of a probe frame (engine/tools/probe/probe_geometry.h);
//  - scene_from_state(): positions from State::x (copied into the scene, float), needles from
//    the NeedleTool read-outs (shaft = tip back along the direction over the needle's length),
//    deposited seeds (4.5 mm x 0.8 mm rods along their needle), the biopsy guide and template holes;
//  - scene_from_snapshot(): positions from a Snapshot (no copy: the scene points into it) and
//    needles/seeds from its DrawList (roles Needle and Seed), for the render thread.
// Options say which overlays to add. The State path calls NeedleTool::seeds(), which allocates;
// the imager itself does not.
#pragma once
#include <string>

#include "engine/contract/snapshot.h"
#include "engine/step/simulation.h"
#include "engine/tools/needle/needle.h"
#include "engine/tools/probe/probe.h"
#include "engine/ultrasound/anatomy.h"
#include "engine/ultrasound/scene.h"

namespace ps::us {

inline constexpr double kSeedLength = 4.5e-3;   // I-125 seed (model 6711): 4.5 mm long [m]
inline constexpr double kSeedRadius = 0.4e-3;   // 0.8 mm diameter [m]

struct SceneOptions {
  bool guide = true;               // biopsy guide line (from the probe)
  bool grid = false;               // brachytherapy template holes
};

ProbeView probe_view(const ProbeFrame& frame, double radius);

// Positions, probe, needles, seeds and overlays from a running simulation. `probe` may be null
// (then the scene keeps its probe view), `needles` may be null.
void scene_from_state(const State& state, const ProbeTool* probe, const NeedleTool* needles, const SceneOptions& opt,
                      UltrasoundScene& scene);

// The probe pose as a Snapshot shows it (for threads that read snapshots only): the body capsule
// (role Probe: back -> tip-hemisphere centre, radius) gives the axis; the biopsy guide (role Guide,
// on the probe's anterior side) gives the roll; without a guide the anterior is the world's +y
// (patient anterior) made perpendicular to the axis. False when the snapshot has no probe.
bool probe_view_from_snapshot(const Snapshot& snapshot, ProbeView& probe);

// Positions from a Snapshot (the scene points into snapshot.x, which must outlive the render),
// rods from its DrawList (capsules with role Needle, spheres or capsules with role Seed), the
// probe from `probe` (the render thread keeps the probe frame it was given with the snapshot).
void scene_from_snapshot(const Snapshot& snapshot, const ProbeView& probe, UltrasoundScene& scene);

// The anatomy of a compiled scenario, with the Model's urethra line (Model::urethra) and the
// calcifications from calcifications.csv beside the mesh file of the component whose role is
// prostate when it exists (the default anatomy, assets/anatomy/; a case without the file has none),
// and the seminal vesicles of seminal_vesicles.obj beside it (engine/anatomy/display_meshes.h).
UltrasoundAnatomy anatomy_for_scenario(const ScenarioSpec& spec, const Model& model);

}  // namespace ps::us
