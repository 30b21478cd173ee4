// Pre-implant plan of a permanent seed implant (`prostatesim plan`): seed positions on template
// lines at 5 mm steps inside the prostate's rest shape, chosen by simulated annealing, and the
// plan's dose-volume indices checked against the usual constraints.
//
// Optimiser (deterministic): candidates are the points at step_mm along each template hole's
// line that lie in the gland, at least min_urethra_mm from the urethra's centre line, on a line
// that does not cross the rectum or bone before them. The dose of one seed at each candidate to
// every structure voxel of a planning grid (2 mm) is tabulated; the loading is then found by
// simulated annealing over that matrix (plan_annealing.h: linear penalties on prostate under- and
// overdose, urethra and rectum overdose and per needle), starting from no seed. The plan is
// evaluated on the 1 mm grid against the constraints; while one is missed the weight of its
// penalty is raised and the annealing resumed from the last loading (at most 8 rounds). The
// first plan that meets them all is returned, else the one that misses them by least.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "engine/dosimetry/dvh.h"
#include "engine/dosimetry/source_models.h"

namespace ps::dosimetry {

struct PlanHole {
  int col = 0, row = 0;
  Vec3 entry_mm = Vec3::Zero();     // where the hole's line leaves the template
  Vec3 direction = Vec3::UnitZ();   // unit, into the patient
};

struct PlanInput {
  const SourceModel* model = nullptr;
  double prescription_gy = 145.0;
  double strength_u = 0.5;          // per seed [U]
  double step_mm = 5.0;             // seed spacing along a line
  double min_urethra_mm = 10.0;     // no seed closer to the urethra's centre line (peripheral loading)
  double urethra_radius_mm = 3.0;   // the urethra as a tube for its DVH
  std::vector<PlanHole> holes;
  std::vector<Vec3> prostate_mm;    // closed surfaces at rest (vertices, faces)
  std::vector<std::array<int, 3>> prostate_faces;
  std::vector<Vec3> rectum_mm;
  std::vector<std::array<int, 3>> rectum_faces;
  std::vector<Vec3> bone_mm;        // may be empty
  std::vector<std::array<int, 3>> bone_faces;
  std::vector<Vec3> urethra_mm;     // centre line
};

struct PlannedNeedle {
  int col = 0, row = 0;
  std::string hole;                 // "D3.5"
  Vec3 entry_mm = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();
  std::vector<double> seed_depths_mm;  // from the entry, deepest first (the order they leave)
};

struct ConstraintCheck {
  std::string name;                 // "prostate V100 >= 95 %"
  double value = 0.0, limit = 0.0;
  std::string unit;
  bool pass = false;
  std::string source;
};

struct Plan {
  std::vector<PlannedNeedle> needles;
  int seeds = 0;
  DosimetryIndices predicted;       // on the 1 mm grid
  std::vector<ConstraintCheck> checks;
  int rounds = 0;                   // annealing rounds run to reach this plan
  double cost = 0.0;                // its annealing cost (plan_annealing.h)
  bool feasible() const;
  std::vector<Seed> seed_list(double strength_u) const;
};

// The constraints (prostate V100 >= 95 %, D90 100-120 % Rx, urethra D10 < 150 %, rectum D2cc
// < Rx) evaluated on the indices, each with its source.
std::vector<ConstraintCheck> check_constraints(const DosimetryIndices& x);

// The dose grid over the gland with a margin (1 mm, 10 mm: the live and report grid).
GridSpec gland_grid(const std::vector<Vec3>& prostate_mm, double margin_mm = 10.0, double spacing_mm = 1.0);
// Structure masks on a grid: prostate and rectum from their closed surfaces, the urethra a tube.
std::vector<uint8_t> structure_mask(const GridSpec& g, const std::vector<Vec3>& prostate_mm,
                                    const std::vector<std::array<int, 3>>& prostate_faces, const std::vector<Vec3>& rectum_mm,
                                    const std::vector<std::array<int, 3>>& rectum_faces, const std::vector<Vec3>& urethra_mm,
                                    double urethra_radius_mm);

// Throws InputError (field "holes", "prostate") when no template line reaches the gland.
Plan optimise_plan(const PlanInput& in);

// The plan as YAML (the file `prostatesim plan` writes; read back by the scene).
std::string plan_yaml(const Plan& p, const PlanInput& in, const std::string& scenario);

}  // namespace ps::dosimetry
