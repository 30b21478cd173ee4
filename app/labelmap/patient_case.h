// A patient's case from a segmentation's label map (`prostatesim make-anatomy --from-labels`):
// one closed surface per organ (label_surface) and a scenario that uses them with the default
// materials, probe and biopsy needle of config/biopsy.yaml.
#pragma once
#include <string>
#include <vector>

#include "app/labelmap/label_surface.h"
#include "app/labelmap/label_volume.h"
#include "engine/mesh/tri_mesh.h"

namespace ps::labelmap {

// One organ of the case: its role, the component it becomes and the label values it is made of.
struct OrganLabels {
  std::string role;          // prostate, bladder, rectum, bone, fat
  std::vector<int> values;   // label values (a '+' list: prostate=1+2 joins two zones)
};

// The roles a case understands, in the order the scenario lists them.
const std::vector<std::string>& case_roles();

// Parses "prostate=1,bladder=2,rectum=3,bone=4,fat=5". Throws InputError naming `option` for an
// unknown role, a value that is not a positive integer, a role or value given twice, or a missing
// prostate or rectum (the probe lies in the rectum; fat is optional: without it the case has a
// fat block 20 mm around the organs).
std::vector<OrganLabels> parse_label_list(const std::string& text, const std::string& option);

struct CaseOrgan {
  std::string role;
  std::vector<int> values;   // empty for a fat block made without a fat label
  TriMesh surface;           // patient RAS [m]
  SurfaceStats stats;
};

struct PatientCase {
  std::string source;        // the label map's file name
  std::vector<CaseOrgan> organs;
  Vec3 probe_entry_m = Vec3::Zero();   // on the rectum's centre line, 32 mm below the prostate centre
  bool probe_entry_in_rectum = false;
};

// Builds every organ's surface (InputError naming the file and the organ's label when one is empty
// or cannot be closed) and places the probe.
PatientCase make_patient_case(const LabelVolume& volume, const std::vector<OrganLabels>& organs);

// The scenario text (file paths relative to the case folder).
std::string case_scenario_yaml(const PatientCase& c);

// Writes <role>.obj for each organ and scenario.yaml into `folder` (which must exist), each file
// atomically, only after everything has been built.
void write_patient_case(const std::string& folder, const PatientCase& c);

}  // namespace ps::labelmap
