// Reader for the scenario's probe: section (called by parse_yaml.cpp). Internal to
// the engine library: it sees yaml-cpp through engine/spec/yaml_reader.h. Keys and units:
// probe:
//   radius_mm: 10              # capsule radius (default 10)
//   length_mm: 120             # modelled shaft, tip-hemisphere centre to back end (default 120)
//   entry_mm: [x, y, z]        # required: anal entry, pivot of tilt and yaw
//   axis: [0, 0, 1]            # rectal axis, insertion direction (default +z)
//   anterior: [0, 1, 0]        # toward the prostate (default +y; made perpendicular to axis)
//   pose: {insertion_mm, offset_mm: [x,y,z], roll_deg, tilt_deg, yaw_deg}   # start pose
//   moves:                     # scripted; each sets some pose fields, reached at the ramp end
//     - {ramp_s: [t0, t1], insertion_mm, offset_mm, roll_deg, tilt_deg, yaw_deg}
//   contact: {mode: contact | imposed, components: [names], rectum: name, prostate: name,
//             couple_distance_mm}
//   limits: {max_speed_mm_s: 50, max_angular_speed_deg_s: 60}
//   needle_guide: {angle_deg: 20, back_mm: 15}
//   template: {distance_mm: 30, pitch_mm: 5, cols: 13, rows: 13, first_row_mm: 10}
#pragma once
#include "engine/spec/scenario_spec.h"
#include "engine/spec/yaml_reader.h"

namespace ps {

void parse_probe_section(const YamlReader& r, const YAML::Node& node, ScenarioSpec& spec);

}  // namespace ps
