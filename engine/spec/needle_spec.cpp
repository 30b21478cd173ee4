#include "engine/spec/needle_spec.h"

#include <cmath>

#include "engine/util/error.h"

namespace ps {

double gauge_diameter(int gauge) {
  // Stubs (Birmingham) iron wire gauge, outer diameter in mm, as used for hypodermic needles
  static constexpr double kMm[] = {3.404, 3.048, 2.769, 2.413, 2.108, 1.829, 1.651, 1.473, 1.270, 1.067, 0.908,
                                   0.819, 0.718, 0.642, 0.566, 0.515, 0.464, 0.413, 0.362, 0.337, 0.312};
  if (gauge < 10 || gauge > 30) return 0.0;
  return kMm[gauge - 10] * 1e-3;
}

bool apply_needle_preset(const std::string& preset, NeedleSpec& s) {
  if (preset == "biopsy_18g") {
    // transrectal core biopsy needle (e.g. 18G x 25 cm); its gun (`gun:` section, defaults in
    // BiopsyGunSpec: 22 mm stroke in 15 ms, 18 mm notch 5 mm behind the trocar tip) fires on cue
    s.gauge = 18;
    s.diameter = gauge_diameter(18);
    s.length = 0.250;
    s.node_spacing = 2e-3;
    return true;
  }
  if (preset == "brachy_18g") {
    // transperineal brachytherapy needle (18G x 20 cm) carrying seeds
    s.gauge = 18;
    s.diameter = gauge_diameter(18);
    s.length = 0.200;
    s.node_spacing = 2e-3;
    return true;
  }
  return false;
}

void validate_needle_spec(const NeedleSpec& s) {
  const std::string& k = s.key;
  auto fail = [&](const std::string& field, const std::string& msg) { throw InputError(s.file, s.line, k + "." + field, msg); };
  auto pos = [&](double v, const std::string& field) {
    if (!(v > 0.0) || !std::isfinite(v)) fail(field, "must be a positive number");
  };
  if (s.gauge <= 0) fail("gauge", "must be a positive gauge number, got " + std::to_string(s.gauge));
  pos(s.diameter, "diameter_mm");
  if (s.diameter > 5e-3) fail("diameter_mm", "a needle thicker than 5 mm is not a needle");
  pos(s.length, "length_mm");
  if (s.length > 0.5) fail("length_mm", "longer than 500 mm");
  pos(s.node_spacing, "node_spacing_mm");
  if (s.node_spacing < 0.2e-3) fail("node_spacing_mm", "below 0.2 mm: thousands of nodes for no gain");
  if (s.node_spacing > 0.5 * s.length) fail("node_spacing_mm", "more than half the needle length: fewer than 3 nodes");
  pos(s.mass, "mass_g");
  pos(s.coupling_stiffness, "coupling_stiffness_n_mm");
  if (!(s.coupling_damping >= 0.0)) fail("coupling_damping_n_s_m", "must be >= 0");
  const double r = 0.5 * s.diameter;
  auto zone = [&](double v, const std::string& field) {
    if (v == 0.0) return;  // automatic
    if (!(v >= r) || !std::isfinite(v))
      fail(field, "zone radius below the needle radius (" + std::to_string(r * 1e3) + " mm): no tissue could be in it");
    if (v > 25e-3) fail(field, "zone radius above 25 mm: the needle would act on tissue far from its shaft");
  };
  zone(s.cutting_radius, "cutting_radius_mm");
  zone(s.friction_radius, "friction_radius_mm");
  pos(s.press_stiffness, "press_stiffness_n_mm");
  pos(s.stick_stiffness, "stick_stiffness_n_mm");
  if (!(s.static_ratio >= 1.0) || s.static_ratio > 10.0) fail("static_ratio", "must be in [1, 10] (static >= kinetic friction)");
  pos(s.cut_velocity, "cut_velocity_mm_s");
  pos(s.max_force, "max_force_n");
  pos(s.max_speed, "max_speed_m_s");
  pos(s.plan_margin, "plan_margin_mm");
  if (!s.start.allFinite()) fail("start_mm", "not finite");
  if (!(std::abs(s.direction.norm() - 1.0) < 1e-9)) fail("direction", "must be a unit vector");
  double max_depth = 0.0;
  for (size_t i = 0; i < s.script.size(); ++i) {
    const auto& p = s.script[i];
    const std::string f = "script[" + std::to_string(i) + "]";
    if (!(p.t >= 0.0) || !std::isfinite(p.t)) fail(f, "time must be >= 0");
    if (i > 0 && !(p.t > s.script[i - 1].t)) fail(f, "times must increase strictly");
    if (!(p.depth >= 0.0) || !std::isfinite(p.depth)) fail(f, "depth must be >= 0 (forward from the start position)");
    if (p.depth > s.length) fail(f, "depth " + std::to_string(p.depth * 1e3) + " mm is more than the needle length");
    max_depth = std::max(max_depth, p.depth);
  }
  if (s.gun) {
    const BiopsyGunSpec& g = *s.gun;
    if (!(g.fire_time >= 0.0) && !std::isnan(g.fire_time)) fail("gun.fire_s", "must be >= 0 (or absent: fired by command)");
    pos(g.stroke, "gun.stroke_mm");
    if (g.stroke > 0.05) fail("gun.stroke_mm", "above 50 mm");
    pos(g.duration, "gun.duration_ms");
    if (g.duration > 0.1) fail("gun.duration_ms", "a spring-loaded gun fires in well under 100 ms");
    if (!(g.settle >= 0.0)) fail("gun.settle_ms", "must be >= 0");
    if (!(g.notch_offset >= 0.0)) fail("gun.notch_offset_mm", "must be >= 0");
    pos(g.notch_length, "gun.notch_length_mm");
    if (g.notch_offset + g.notch_length > s.length) fail("gun.notch_length_mm", "notch extends beyond the needle");
    if (g.notch_radius != 0.0 && !(g.notch_radius >= r)) fail("gun.notch_radius_mm", "below the needle radius");
    max_depth += g.stroke;
    if (max_depth > s.length) fail("gun.stroke_mm", "scripted depth plus the stroke exceeds the needle length");
  }
  for (size_t i = 0; i < s.seed_depths.size(); ++i) {
    const double d = s.seed_depths[i];
    const std::string f = "seeds_mm[" + std::to_string(i) + "]";
    if (!(d > 0.0) || !std::isfinite(d)) fail(f, "seed depth must be positive");
    if (d > s.length) fail(f, "seed depth " + std::to_string(d * 1e3) + " mm is beyond the needle (length " +
                                   std::to_string(s.length * 1e3) + " mm)");
    if (!s.script.empty() && d > max_depth + 1e-9)
      fail(f, "seed depth " + std::to_string(d * 1e3) + " mm is beyond the deepest scripted tip depth " +
                  std::to_string(max_depth * 1e3) + " mm");
  }
  if (s.seed_depths.size() > 64) fail("seeds_mm", "more than 64 seeds in one needle");
}

}  // namespace ps

namespace ps {

std::vector<std::string> twelve_core_sites() {
  std::vector<std::string> out;
  for (const char* side : {"right", "left"})
    for (const char* level : {"base", "mid", "apex"})
      for (const char* ml : {"lateral", "medial"}) out.push_back(std::string(side) + " " + level + " " + ml);
  return out;
}

}  // namespace ps
