// Reads the `needles:` section of a scenario file (engine-internal: includes yaml-cpp through
// engine/spec/yaml_reader.h; only parse_yaml.cpp and needle_spec_yaml.cpp include it).
//
// needles:
//   puncture_n: {liver: 2.45}          # surface puncture weight k_c per component [N]
//   event_capacity: 4096
//   instruments:
//     - name: n1
//       preset: biopsy_18g             # or brachy_18g; keys below override it
//       gauge: 18                      # or diameter_mm
//       length_mm: 200
//       node_spacing_mm: 2
//       mass_g: 10
//       coupling_stiffness_n_mm: 2
//       coupling_damping_n_s_m: 20
//       cutting_radius_mm / friction_radius_mm: 4   (omit: automatic)
//       press_stiffness_n_mm: 2
//       stick_stiffness_n_mm: 0.5
//       static_ratio: 1.0
//       cut_velocity_mm_s: 1
//       max_force_n: 50
//       max_speed_m_s: 3
//       plan_margin_mm: 10
//       start_mm: [0, 0, 5]            # tip at t = 0
//       direction: [0, 0, -1]
//       script: [[0, 0], [10, 30]]     # [t_s, depth_mm] along direction from start_mm
//       seeds_mm: [20, 25]             # planned seed depths (brachytherapy)
//       gun: {fire_s: 2, stroke_mm: 22, duration_ms: 15, settle_ms: 5,
//             notch_offset_mm: 5, notch_length_mm: 18, notch_radius_mm: 3}
//       tumour: [lesion]                # components or particle tags counted as tumour in a core
//       target_mm: [5, 0, -20]          # aimed point (metrics; default: the script's planned end)
//       planned_site: right mid lateral # planned 12-core biopsy site (metrics: zone coverage)
#pragma once
#include "engine/spec/yaml_reader.h"
#include "engine/spec/needle_spec.h"

namespace ps {

NeedleSetSpec parse_needles_yaml(const YamlReader& r, const YAML::Node& node);

}  // namespace ps
