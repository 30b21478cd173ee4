// Training metrics of a needle session (issue 13, docs/metrics.md), fed from the needle tool's
// read-outs and events after every tick, outside the step. Construction sizes everything;
// observe() never allocates; finish() builds the report at the end.
//
// Per needle:
//  * error to its target: the target (NeedleSpec::target, default the deepest point of the script)
//    is a material point carried by the tissue (TrackedPoint). It is compared, at the needle's
//    decisive moment, with where the needle put its sample:
//      - biopsy gun: at the core, the centre of the notch
//        (tip - (notch_offset + notch_length / 2) x direction), default target the planned
//        notch centre after the stroke;
//      - otherwise: the tip, at the tick of its deepest planned depth.
//    error = |sample - target now|, split into lateral (perpendicular to the needle) and depth
//    (signed along it, > 0: too deep).
//  * punctures (Puncture events) and re-insertions: a forward stroke that follows a withdrawal of
//    more than kReinsertStroke along the planned line (a needle pulled back and pushed again);
//  * peak and mean axial force over the ticks in contact with tissue (tick averages) [N];
//  * insertion time: first contact to the decisive moment (last seed for a seed needle) [s];
//  * structures hit: urethra, rectal wall, bladder, bone, from the Contact / Puncture / BoneHit
//    events on those organs (engine/model/role.h: by component name, any rigid component = bone),
//    the Urethra event, and
//    for the urethra also the tip coming within MetricsOptions::urethra_radius of the urethra
//    centre line (carried by the tissue) when one is given. The component the needle enters
//    first is its route (the rectal wall for a transrectal biopsy), not a hit, unless it is
//    punctured a second time.
// Biopsy: each core's 12-core site (core_site), lesion hit (tumour particles in the notch) and
// lesion length; cores per zone; cores outside the gland; coverage = planned sites
// (NeedleSpec::planned_site, planned_sites) with a core whose site label starts with them / planned
// sites; a needle whose target lies in tumour tissue is a targeted lesion, missed when its core
// holds no tumour. A needle with planned sites (the 12-core protocol with one needle in the guide)
// is scored per core: its error is the mean over its cores of the distance from the notch to the
// nearest planned site's centre (engine/metrics/planned_sites.h), carried by the tissue, and each
// lesion tag of the model is a targeted lesion, missed when none of its cores holds it.
// Brachytherapy: each deposited seed against its planned site carried by the tissue (mean, max
// error) and seeds whose position is outside the gland surface (winding number < 1/2); the
// implant's dose (TG-43U1) planned and achieved (implant_dosimetry.h).
// Procedure time: first contact of any needle to the last needle's decisive moment [s].
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/metrics/implant_dosimetry.h"
#include "engine/metrics/planned_sites.h"
#include "engine/metrics/tracked_point.h"
#include "engine/state/state.h"
#include "engine/tools/needle/needle.h"

namespace ps {

inline constexpr double kReinsertStroke = 2e-3;  // withdrawal that makes the next push a re-insertion [m]
inline constexpr int kMaxTrackedCores = 64;      // cores per needle whose error to a planned site is kept

// Probe contact force on the rectal wall above which the time is counted [N]. PROVISIONAL: no
// published measurement of TRUS probe force during biopsy was found; 10 N is the order of the
// gland-deforming pushes of the probe validation cases (docs/metrics.md).
inline constexpr double kProbeForceThreshold = 10.0;

struct MetricsOptions {
  std::string gland;               // component whose surface is the gland (seeds outside it);
                                   // empty: the first whose role is prostate
  std::vector<Vec3> urethra;       // urethra centre line at rest [m] (Model::urethra; empty: by
                                   // the urethra role's component only)
  double urethra_radius = kUrethraRadius;  // [m]
  DosimetryOptions dosimetry;      // isotope, prescription, seed strength (its gland: `gland`)
};

struct NeedleMetrics {
  std::string name;
  bool scored = false;              // reached its decisive moment in tissue
  std::string measured_at;          // "core" | "deepest" | "" (never inserted)
  Vec3 target_rest = Vec3::Zero();  // [m]
  Vec3 target_now = Vec3::Zero();   // target at the decisive moment [m]
  Vec3 sample = Vec3::Zero();       // notch centre or tip at that moment [m]
  double error = NAN, lateral_error = NAN, depth_error = NAN;  // [m]
  int punctures = 0;
  int reinsertions = 0;
  double peak_force = 0.0, mean_force = 0.0;  // [N]
  double first_contact = NAN;       // [s]
  double insertion_time = NAN;      // [s]
  std::vector<std::string> structures_hit;   // "urethra", "rectal wall", "bladder", "bone", "capsule exit"
  int capsule_exits = 0;            // times the tip left the gland through its capsule (GlandExit)
  bool target_in_lesion = false;
};

struct CoreMetrics {
  std::string needle, site, planned_site;
  bool taken = false, lesion_hit = false;
  double lesion_length = 0.0, notch_length = 0.0;  // [m]
  double time = 0.0;                // [s]
  Vec3 notch_centre = Vec3::Zero(); // where the notch's centre was when the core was taken [m]
  double site_error = NAN;          // planned sites: notch (segment) to the nearest site centre [m]
};

struct SeedMetrics {
  std::string needle;
  int index = -1;
  bool deposited = false, outside_gland = false;
  double error = NAN;               // |seed - planned site carried by the tissue| [m]
};

struct SessionReport {
  std::string scenario;
  double duration = 0.0;            // simulated [s]
  double procedure_time = 0.0;      // [s]
  std::vector<NeedleMetrics> needles;
  // biopsy
  std::vector<CoreMetrics> cores;
  std::vector<std::pair<std::string, int>> cores_per_zone;  // site label -> cores
  std::vector<std::string> planned_sites;
  std::vector<PlannedSite> planned_site_centres;  // each planned site's peripheral-zone centre at rest
  double coverage = NAN;            // of the planned sites, NAN when none planned
  int cores_outside_gland = 0;      // cores whose notch held no prostate tissue
  int lesions_targeted = 0, lesions_missed = 0;
  // brachytherapy
  std::vector<SeedMetrics> seeds;
  double seed_error_mean = NAN, seed_error_max = NAN;  // [m]
  int seeds_outside_gland = 0;
  bool gland_known = false;
  DosimetryReport dosimetry;        // planned and achieved TG-43U1 indices (computed: has seeds)
  // targeting summary over the scored needles
  double mean_error = NAN, max_error = NAN;  // [m]
  // structures_hit: the needles' structures hit, a capsule exit aside (scored by capsule_exits)
  int structures_hit = 0, reinsertions = 0, punctures = 0;
  int capsule_exits = 0;            // the needles' exits through the gland's capsule
  bool faulted = false;
  // the probe's contact force (the tissue's force on it, tick mean): peak and time above
  // kProbeForceThreshold; NAN without a probe
  double probe_peak_force = NAN;    // [N]
  double probe_time_above = NAN;    // [s]
};

class SessionMetrics {
 public:
  // Throws InputError when a target lies outside the scene (naming the needle's target_mm).
  SessionMetrics(const Model& m, const NeedleTool& tool, const MetricsOptions& opt = {});
  // After each tick (outside the step): no allocation.
  void observe(const NeedleTool& tool, const State& s);
  // After each tick of a scene with a probe: its contact force [N] over the tick dt [s].
  void observe_probe(double force, double dt);
  SessionReport finish(const NeedleTool& tool, const State& s, bool faulted = false) const;

 private:
  struct Track {
    TrackedPoint target;
    double sample_back = 0.0;       // sample point behind the tip [m] (notch centre for a gun)
    bool gun = false;
    bool decisive = false;          // sample taken
    double decisive_time = NAN;
    Vec3 sample = Vec3::Zero(), target_now = Vec3::Zero(), dir = -Vec3::UnitZ();
    double best_depth = -INFINITY;  // deepest planned depth seen [m]
    // re-insertion hysteresis on the planned depth
    bool forward = true;
    double extreme = 0.0;
    int reinsertions = 0;
    double peak_force = 0.0, force_sum = 0.0;
    int64_t force_ticks = 0;
    double first_contact = NAN;
    double last_seed_time = NAN;
    int punctures = 0;
    int entry = -1;                 // first component entered (route)
    int entry_punctures = 0;
    uint32_t hit_mask = 0;          // bit per kStructure*
    int gland_exits = 0;            // GlandExit events
    bool lesion_target = false;
    // a needle in the probe's guide takes several cores (NeedleSpec::guide): a push after a core
    // is the next core, not a re-insertion, and its route is punctured again on every pass
    bool guided = false;
    int cores_seen = 0, cores_at_forward = 0;
    // planned sites (NeedleSpec::planned_sites): their centres carried by the tissue, and each
    // core's distance from its notch (the segment) to the nearest centre [m]
    std::vector<TrackedPoint> sites;
    std::vector<double> core_error;  // capacity kMaxTrackedCores
  };
  const Model* model_;
  MetricsOptions opt_;
  int gland_ = -1;
  std::vector<Track> tracks_;
  std::vector<std::vector<TrackedPoint>> seed_sites_;  // [needle][seed]
  std::vector<TrackedPoint> urethra_;
  std::vector<Vec3> urethra_now_;                      // scratch, sized once
  std::vector<uint8_t> structure_of_;                  // [components] kStructure* bit or 0
  int64_t events_seen_ = 0;
  double first_contact_ = NAN;
  double probe_peak_ = NAN, probe_above_ = 0.0;
};

// Names of the structure bits (urethra, rectal wall, bladder, bone).
const char* structure_name(int bit);
// Structure bit of a component by its name and kind (0: none).
uint32_t structure_of(const Component& c);

}  // namespace ps
