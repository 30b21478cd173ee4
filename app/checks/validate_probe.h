// Probe and organ-filling measurements (issue 5; paper §5.3 Fig. 11-12, §5.4.1) on the primitive
// pelvis scene config/validation/probe_pelvis_box.yaml: how far the prostate moves (mean, max,
// per zone base/mid/apex) when the bladder doubles, when the probe is pushed or tilted, in the
// paper's imposed mode, and when the probe pushes against a doubled bladder. There is no
// external reference for these numbers (the paper gives a coloured figure only): they are
// reported, while the hard properties (volumes exact, no penetration) are checked.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "app/checks/validation.h"
#include "engine/model/model.h"
#include "engine/tools/probe/displacement_field.h"

namespace ps::app {

struct DisplacementStudy {
  std::string name;                  // bladder_doubling, probe_push, probe_tilt, probe_imposed, probe_full_bladder
  std::shared_ptr<const Model> model;
  std::vector<Vec3> ref, x;          // positions before the load and settled after it [m]
  DisplacementStats prostate;        // u = x - ref over the prostate, zones along +z [m]
  double worst_volume_error = 0.0;   // max |V/V_target - 1| of bladder and prostate after any tick
  double worst_penetration = 0.0;    // deepest movable particle inside the probe after any tick [m]
  Vec3 probe_force = Vec3::Zero();   // tissue on probe at the end, tick mean [N]
  std::vector<std::string> reports;  // clamps reported by the tools
};

// Runs one study by name (throws std::invalid_argument for an unknown name, std::runtime_error
// on a simulation fault).
DisplacementStudy run_displacement_study(const std::string& source_dir, const std::string& name);
// Per-particle displacement file of the study (engine/tools/probe/displacement_field.h CSV), every
// component, zones along +z, written atomically.
void write_study_csv(const DisplacementStudy& study, const std::string& path);

// Folder where the validation cases write <case>_displacement.csv (created when written).
// Default "out/validate", relative to the working directory; `prostatesim validate --out DIR`.
void set_displacement_output_dir(const std::string& dir);
const std::string& displacement_output_dir();

std::vector<ValidationCase> probe_validation_cases();

}  // namespace ps::app
