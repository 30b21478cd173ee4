// Dosimetry of a scene's seed implant (issue 46, docs/dosimetry.md): TG-43U1 total dose of the
// seeds where the tissue carried them, each along its needle's track, on the deformed organs
// (prostate and rectum from their particle surfaces, the urethra a tube around its centre line
// carried by the tissue), beside the plan: the same seeds at their planned sites on the organs at
// rest. Reader side: allocates, reads positions (a State's or a snapshot's), never the step.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "engine/dosimetry/dvh.h"
#include "engine/dosimetry/plan.h"
#include "engine/model/model.h"
#include "engine/tools/needle/needle.h"

namespace ps {

class ProbeTool;

struct DosimetryOptions {
  std::string isotope = "I125_6711";
  double prescription_gy = 145.0;   // I-125 monotherapy (ABS)
  double strength_u = 0.5;          // air-kerma strength per seed [U]
  std::string gland;                // empty: the first component whose role is prostate
  std::string rectum;               // empty: the first component whose role is rectum
  double urethra_radius_mm = kUrethraRadius * 1e3;
};

struct DosimetryReport {
  bool computed = false;            // the scene has seeds and a gland
  std::string isotope;
  double prescription_gy = 0.0, strength_u = 0.0;
  int seeds_planned = 0, seeds_deposited = 0;
  dosimetry::DosimetryIndices planned, achieved;
  dosimetry::DvhCurve dvh_planned, dvh_achieved;
};

// Component c's closed particle surface in millimetres at positions x [m] (empty if c < 0 or it
// has none).
void organ_surface_mm(const Model& m, int c, const std::vector<Vec3>& x, std::vector<Vec3>& vertices_mm,
                      std::vector<std::array<int, 3>>& faces);

// The seeds the needles deposited, at their current (tissue-carried) sites, along their needles.
std::vector<dosimetry::Seed> deposited_seeds(const NeedleTool& tool, double strength_u);
// Every planned seed at its planned site (rest frame).
std::vector<dosimetry::Seed> planned_seeds(const NeedleTool& tool, double strength_u);

// Planned (rest organs) and achieved (organs at x) indices and DVHs; urethra centre lines in m.
DosimetryReport implant_dosimetry(const Model& m, const std::vector<Vec3>& x, const NeedleTool& tool,
                                  const std::vector<Vec3>& urethra_rest, const std::vector<Vec3>& urethra_now,
                                  const DosimetryOptions& opt);

// The optimiser's input from the scene at rest: the probe's template holes, the organs, the
// urethra (InputError naming "isotope" for an unknown model).
dosimetry::PlanInput plan_input(const Model& m, const ProbeTool& probe, const std::vector<Vec3>& urethra_rest,
                                const DosimetryOptions& opt);

}  // namespace ps
