// Puncture of a wall against insertion speed (issue 9, "fast insertion is physical"): measured
// needle mechanics say the force at rupture and the deflection before it fall as the insertion
// speed rises (Mahvash & Dupont, IEEE TBME 57:934, 2010). A transrectal-like scene: the needle
// starts in the lumen of a closed wall (fill: surface, as the rectum of config/biopsy.yaml),
// soft fat beyond it, 6 substeps of a 1 ms tick (the default biopsy scene runs 3 of a 2 ms tick);
// driven at constant speed from 3 mm/s to
// the biopsy gun's 1.5 m/s.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps {
namespace {

// Wall top at z = 0, fat from z = 3 mm; the tip starts 2 mm inside the lumen and travels 16 mm.
// The puncture weight 0.6 N is one the quasi-static contact force reaches smoothly on this small
// wall (its force-deflection flattens near 0.9 N, where a rupture is set by the tip crossing a
// lattice edge rather than by the force: 1.5 N ruptured at 8.6, 8.8, 12.6 and 13.5 mm at 3, 10,
// 100 and 200 mm/s, measured with this scene), so that the test sees the rate effect, not the lattice.
std::string wall_scene(double v_mm_s) {
  constexpr double kTravel = 16.0;  // [mm]
  char script[96];
  std::snprintf(script, sizeof script, "[[0, 0], [%.6f, %.1f]]", kTravel / v_mm_s, kTravel);
  return std::string(
             "name: wall_speed\n"
             "time: {dt_ms: 1, substeps: 6, duration_s: 1}\n"
             "gravity_m_s2: [0, 0, 0]\n"
             "materials:\n"
             "  wall: {young_kpa: 20, density_kg_m3: 1040, damping_1_s: 40, k_c_n: 1.0, k_f_n: 0.03}\n"
             "  fat: {model: tet, young_kpa: 3, density_kg_m3: 940, damping_1_s: 40, k_c_n: 0.3, k_f_n: 0.02}\n"
             "components:\n"
             "  - {name: rectum, material: wall, fill: surface, spacing_mm: 5, box: {min_mm: [-15, -15, -25], max_mm: [15, 15, 0]}}\n"
             "  - {name: fat, material: fat, spacing_mm: 6, box: {min_mm: [-15, -15, 3], max_mm: [15, 15, 27]}}\n"
             "links:\n"
             "  - {a: rectum, b: fat, distance_mm: 7}\n"
             "constraints:\n"
             "  - fix: {component: rectum, region: {box: {min_mm: [-100, -100, -26], max_mm: [100, 100, -12]}}}\n"
             "  - fix: {component: fat, region: {box: {min_mm: [-100, -100, 26], max_mm: [100, 100, 28]}}}\n"
             "needles:\n"
             "  puncture_n: {rectum: 0.6}\n"
             "  instruments:\n"
             "    - {name: b, preset: biopsy_18g, start_mm: [1.1, 0.7, -2], direction: [0, 0, 1], script: ") +
         script + "}\n";
}

struct Rupture {
  bool found = false;
  double contact_force = 0.0;   // on the wall at rupture [N]
  double axial_force = 0.0;     // total on the needle, peak up to the rupture [N]
  double tenting = 0.0;         // tip beyond the wall's rest position at rupture [m]
  bool touched_beyond = false;  // cutting or friction before the rupture
};

Rupture run(double v_mm_s) {
  auto s = test::make_needle_scene(wall_scene(v_mm_s));
  const int rectum = s.model->find_component("rectum");
  Rupture r;
  const int ticks = static_cast<int>(16.0 / v_mm_s * 1e3) + 50;
  for (int i = 0; i < ticks && !s.tool->component_entered(0, rectum); ++i) {
    EXPECT_TRUE(s.sim->tick()) << s.sim->state().fault.describe(*s.model);
    const NeedleReadout& ro = s.tool->readout(0);
    if (!s.tool->component_entered(0, rectum))
      r.touched_beyond |= ro.cutting_force != 0.0 || ro.friction_force != 0.0 || ro.engaged_nodes > 0;
  }
  for (const NeedleEvent& e : s.tool->events().snapshot())
    if (e.kind == NeedleEventKind::Puncture && e.component == rectum && !r.found) {
      r.found = true;
      r.contact_force = e.value;
      r.axial_force = e.force;
      r.tenting = e.position.z();  // the wall rests at z = 0, the needle runs along +z
    }
  return r;
}

TEST(NeedleSpeed, PunctureForceAndTentingDoNotGrowWithSpeed) {
  const double speeds[] = {3.0, 30.0, 100.0, 300.0, 1500.0};  // [mm/s]; the gun: ~1.5 m/s
  Rupture prev;
  for (double v : speeds) {
    const Rupture r = run(v);
    SCOPED_TRACE("speed " + std::to_string(v) + " mm/s");
    ASSERT_TRUE(r.found) << "the wall must be punctured within the 16 mm stroke";
    std::printf("  %7.1f mm/s: contact force at rupture %.4f N, axial force %.4f N, tenting %.3f mm\n", v, r.contact_force,
                r.axial_force, r.tenting * 1e3);
    EXPECT_FALSE(r.touched_beyond) << "nothing beyond an intact wall touches a needle still in its lumen";
    EXPECT_LE(r.contact_force, 0.6 + 1e-12) << "the wall breaks at its threshold, evaluated every substep";
    EXPECT_LE(r.axial_force, 0.6 + 1e-12) << "only the wall resists the needle before the puncture";
    if (prev.found) {
      EXPECT_LE(r.axial_force, prev.axial_force + 1e-12);
      // the rupture is found at the substep, so the tip position at rupture is known to one
      // substep's travel v h (0.25 mm at 1.5 m/s, 0.5 um at 3 mm/s); measured, the tenting falls
      // (5.83, 5.79, 5.71 mm, then 0.02 and 0.07 mm at 0.3 and 1.5 m/s: rupture at impact)
      const double h = 1e-3 / 6;  // substep [s]
      EXPECT_LE(r.tenting, prev.tenting + v * 1e-3 * h);
    }
    prev = r;
  }
  EXPECT_LT(prev.tenting, 1e-3) << "a gun stroke breaches the wall at impact, with under 1 mm of tenting";
}

}  // namespace
}  // namespace ps
