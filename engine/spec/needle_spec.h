// Needle plan of a scenario (paper §4.2): rigid needles as lines of nodes, each driven along a
// commanded path through a spring-damper coupling. Mirrors the `needles:` section of a scenario
// file, already in SI units (files use mm, g, ms; converted once in needle_spec_yaml.cpp).
// Kept free of yaml-cpp and of the Model so the scenario editor can hold and change it.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

// One point of the insertion script: tip depth along the needle direction from its start
// position, reached at time t; linear in between, held before the first and after the last.
struct NeedleScriptPoint {
  double t = 0.0;                  // [s]
  double depth = 0.0;              // [m], >= 0 forward along `direction` from `start`
};

// Spring-loaded biopsy gun: on firing, the commanded depth advances by `stroke` within
// `duration` on top of the script; the core is taken `settle` after the stroke ends.
struct BiopsyGunSpec {
  double fire_time = 0.0;          // [s]; NaN: armed, fired by a live FireGun command only
  double stroke = 22e-3;           // [m]
  double duration = 0.015;         // [s] (real guns: ~10-30 ms)
  double settle = 0.005;           // [s]
  double notch_offset = 5e-3;      // notch start behind the tip (trocar length) [m]
  double notch_length = 18e-3;     // [m]
  double notch_radius = 0.0;       // sampling radius around the axis [m]; 0: friction radius
};

struct NeedleSpec {
  std::string name;
  std::string preset;              // "", "biopsy_18g" or "brachy_18g" (defaults below are 18G)
  int gauge = 18;                  // Stubs/Birmingham wire gauge
  double diameter = 1.270e-3;      // outer diameter [m] (from the gauge unless given)
  double length = 0.200;           // shaft length, tip to hub [m]
  double node_spacing = 2e-3;      // distance between needle nodes [m]
  double mass = 0.010;             // needle + hub + driver, moved by the coupling [kg]
  double coupling_stiffness = 2000.0;  // commanded pose -> needle spring [N/m]
  double coupling_damping = 20.0;      // commanded velocity -> needle damper [N s/m]
  // zones of interest (0: automatic, 1.0 x the largest tissue spacing near the path, so that
  // every node zone inside tissue holds particles; see needle.h)
  double cutting_radius = 0.0;     // ball ahead of the tip [m]
  double friction_radius = 0.0;    // ball around each node [m]
  double press_stiffness = 2000.0; // tip-on-surface contact stiffness before puncture [N/m]
  double stick_stiffness = 500.0;  // virtual tissue particle spring per node [N/m]
  double static_ratio = 1.0;       // static / kinetic friction threshold (>= 1)
  double cut_velocity = 1e-3;      // cutting force ramps in over this forward speed [m/s]
  double max_force = 50.0;         // coupling force clamp (absurd commands) [N]
  double max_speed = 3.0;          // needle speed clamp [m/s]
  double plan_margin = 10e-3;      // tissue displacement tolerated around the planned line [m]
  Vec3 start = Vec3::Zero();       // tip position at t = 0 [m]
  Vec3 direction = -Vec3::UnitZ(); // insertion direction (unit)
  std::vector<NeedleScriptPoint> script;  // empty: hold at start (interactive commands)
  std::vector<double> seed_depths; // brachytherapy seeds, planned depths along the path [m]
  std::optional<BiopsyGunSpec> gun;
  // core sample: components or particle tags that are tumour (empty: those whose role is lesion,
  // engine/model/role.h)
  std::vector<std::string> tumour;
  // training metrics (engine/metrics): the point the trainee aims at, at rest [m], carried by the
  // tissue while it moves (absent: the deepest point of the script, start + depth x direction),
  // and for a biopsy the planned 12-core site ("right mid lateral", anatomy::zone_label without
  // the zone) whose coverage is scored
  std::optional<Vec3> target;
  std::string planned_site;
  // a biopsy needle that takes several cores: the planned 12-core sites it should cover, each
  // aimed at through the centre of that site's peripheral zone (`planned_sites: 12-core`)
  std::vector<std::string> planned_sites;
  // "biopsy": the needle rides in the probe's biopsy guide. Its entry and direction follow the
  // probe's pose every substep (start / direction: the guide at the probe's start pose, set by
  // build_scene); its depth is commanded live, and after each core, back in the guide, it is
  // re-armed and fires again. "": a free needle on its own start / direction.
  std::string guide;
  // where it came from, for errors found later against the compiled model
  std::string file;
  int line = 0;
  std::string key;                 // e.g. "needles.instruments[0]"
};

struct NeedleSetSpec {
  // puncture weight k_c on the surface particles of a component (capsule, rectal or bladder
  // wall, skin): the force the tip must reach to breach it [N]. Components not listed have no
  // membrane: their surface is cut like their interior.
  std::vector<std::pair<std::string, double>> puncture;
  std::vector<NeedleSpec> needles;
  int event_capacity = 4096;       // ring buffer of needle events
  std::string file;
  int line = 0;
};

// The systematic 12-core scheme (base / mid / apex x lateral / medial x right / left), as the
// site labels anatomy::zone_label gives them without the zone ("right base lateral", ...).
std::vector<std::string> twelve_core_sites();

// Outer diameter of a needle gauge [m] (Stubs); 0 when the gauge is not tabulated (10..30).
double gauge_diameter(int gauge);

// Defaults of a preset applied to `spec` (fields not given in the file); false if unknown.
bool apply_needle_preset(const std::string& preset, NeedleSpec& spec);

// Checks one needle on its own (no model): positive sizes, zone sizes that make sense, a
// monotone script, seeds within the needle and the scripted depth, gun settings. Throws
// InputError naming file:line and the field.
void validate_needle_spec(const NeedleSpec& spec);

}  // namespace ps
