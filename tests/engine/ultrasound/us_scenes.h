// Scenes for the ultrasound tests and bench/ultrasound_bench.cpp: the biopsy scenario's anatomy
// (config/biopsy.yaml, compiled once) with its probe, a synthetic homogeneous box, deformations.
#pragma once
#include <cmath>
#include <memory>
#include <string>

#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/probe/probe.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/ultrasound/imager.h"

namespace ps::test {

struct UsBiopsyScene {
  ScenarioSpec spec;
  std::shared_ptr<const Model> model;
  us::UltrasoundAnatomy anatomy;
  // The probe at the scenario's initial pose but 40 mm in (tip-hemisphere centre at z = +8 mm,
  // mid-gland to base), where the transverse plane cuts the gland: the pose these tests and their
  // figures (docs/ultrasound.md) are taken at. The scenario starts further in, its sagittal plane
  // showing base to apex (anatomy_planes_test.cpp).
  us::ProbeView probe;
  us::UltrasoundSettings settings;
};

inline const UsBiopsyScene& us_biopsy_scene() {
  static const UsBiopsyScene s = [] {
    UsBiopsyScene b;
    b.spec = parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
    b.model = compile_scenario(b.spec);
    b.anatomy = us::anatomy_for_scenario(b.spec, *b.model);
    const RectalFrame rf = rectal_frame(*b.spec.probe);
    ProbePose pose = b.spec.probe->pose;
    pose.insertion = 0.040;
    b.probe = us::probe_view(probe_frame(*b.spec.probe, rf, pose), b.spec.probe->radius);
    b.settings = us::settings_for_probe(*b.spec.probe);
    return b;
  }();
  return s;
}

// Positions of `m` at rest, as the float array of a Snapshot.
inline std::vector<float> rest_positions(const Model& m) {
  std::vector<float> x(3 * m.rest_pos.size());
  for (size_t p = 0; p < m.rest_pos.size(); ++p)
    for (int d = 0; d < 3; ++d) x[3 * p + d] = static_cast<float>(m.rest_pos[p][d]);
  return x;
}

// An ultrasound scene of positions `x` (kept alive by the caller) seen from `probe`.
inline us::UltrasoundScene scene_of(const std::vector<float>& x, const us::ProbeView& probe) {
  us::UltrasoundScene sc;
  sc.x = x.data();
  sc.particle_count = static_cast<int>(x.size() / 3);
  sc.probe = probe;
  return sc;
}

// The probe moved along its axis by `advance` [m] and rolled by `roll` [rad].
inline us::ProbeView moved_probe(const us::ProbeView& p, double advance, double roll) {
  us::ProbeView q = p;
  q.tip_centre += advance * p.axis;
  q.anterior = std::cos(roll) * p.anterior + std::sin(roll) * p.lateral;
  q.lateral = p.axis.cross(q.anterior);
  return q;
}

// A homogeneous cube of Soft tissue (12 triangles over 8 corner particles), side `side` [m],
// centred at `centre`.
inline us::UltrasoundAnatomy box_anatomy(const Vec3& centre, double side) {
  us::UltrasoundAnatomy a;
  const double h = 0.5 * side;
  for (int k = 0; k < 8; ++k) a.rest.push_back(centre + Vec3(k & 1 ? h : -h, k & 2 ? h : -h, k & 4 ? h : -h));
  us::UsComponent c;
  c.name = "block";
  c.tissue = us::Tissue::Soft;
  c.first_particle = 0;
  c.particle_count = 8;
  c.spacing = side;
  c.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  a.components.push_back(c);
  a.component_index = {0};
  return a;
}

}  // namespace ps::test
