// `needles:` section of a scenario file -> NeedleSetSpec (mm, g, ms in the file; SI here).
#include <cmath>
#include "engine/tools/needle/needle_spec_yaml.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/util/error.h"

namespace ps {

namespace {

constexpr double kMm = 1e-3;

NeedleSpec parse_needle(const YamlReader& r, const YAML::Node& v, int index) {
  const std::string k = "needles.instruments[" + std::to_string(index) + "]";
  r.only_keys(v, k,
              {"name", "preset", "gauge", "diameter_mm", "length_mm", "node_spacing_mm", "mass_g", "coupling_stiffness_n_mm",
               "coupling_damping_n_s_m", "cutting_radius_mm", "friction_radius_mm",
               "press_stiffness_n_mm", "stick_stiffness_n_mm", "static_ratio", "cut_velocity_mm_s", "max_force_n",
               "max_speed_m_s", "plan_margin_mm", "start_mm", "direction", "script", "seeds_mm", "gun", "tumour",
               "target_mm", "planned_site", "guide", "planned_sites"});
  NeedleSpec s;
  s.file = r.file();
  s.line = YamlReader::line_of(v);
  s.key = k;
  s.name = v["name"] ? r.string(v["name"], k + ".name") : "needle" + std::to_string(index);
  if (v["preset"]) {
    s.preset = r.string(v["preset"], k + ".preset");
    if (!apply_needle_preset(s.preset, s)) r.fail(v["preset"], k + ".preset", "unknown preset '" + s.preset + "' (biopsy_18g, brachy_18g)");
  }
  if (v["gauge"]) {
    s.gauge = r.integer(v["gauge"], k + ".gauge");
    if (s.gauge <= 0) r.fail(v["gauge"], k + ".gauge", "must be a positive gauge number");
    s.diameter = gauge_diameter(s.gauge);
    if (s.diameter == 0.0 && !v["diameter_mm"])
      r.fail(v["gauge"], k + ".gauge", "gauge not tabulated (10..30): give diameter_mm");
  }
  if (v["diameter_mm"]) s.diameter = r.positive(v["diameter_mm"], k + ".diameter_mm") * kMm;
  auto pos = [&](const char* key, double scale, double& out) {
    if (v[key]) out = r.positive(v[key], k + "." + key) * scale;
  };
  pos("length_mm", kMm, s.length);
  pos("node_spacing_mm", kMm, s.node_spacing);
  pos("mass_g", 1e-3, s.mass);
  pos("coupling_stiffness_n_mm", 1e3, s.coupling_stiffness);
  if (v["coupling_damping_n_s_m"]) s.coupling_damping = r.non_negative(v["coupling_damping_n_s_m"], k + ".coupling_damping_n_s_m");
  pos("cutting_radius_mm", kMm, s.cutting_radius);
  pos("friction_radius_mm", kMm, s.friction_radius);
  pos("press_stiffness_n_mm", 1e3, s.press_stiffness);
  pos("stick_stiffness_n_mm", 1e3, s.stick_stiffness);
  pos("static_ratio", 1.0, s.static_ratio);
  pos("cut_velocity_mm_s", kMm, s.cut_velocity);
  pos("max_force_n", 1.0, s.max_force);
  pos("max_speed_m_s", 1.0, s.max_speed);
  pos("plan_margin_mm", kMm, s.plan_margin);
  if (v["guide"]) {
    s.guide = r.string(v["guide"], k + ".guide");
    if (s.guide != "biopsy") r.fail(v["guide"], k + ".guide", "unknown guide '" + s.guide + "' (biopsy: the probe's biopsy guide)");
    // in the guide the path is the probe's: start and direction follow its pose (build_scene)
    if (v["start_mm"]) r.fail(v["start_mm"], k + ".start_mm", "a needle in the probe's guide takes its start from the probe");
    if (v["direction"]) r.fail(v["direction"], k + ".direction", "a needle in the probe's guide takes its direction from the probe");
  } else {
    s.start = r.vec3(r.require(v, k, "start_mm"), k + ".start_mm", kMm);
    s.direction = r.unit_vec3(r.require(v, k, "direction"), k + ".direction");
  }
  if (const YAML::Node sc = v["script"]) {
    if (!sc.IsSequence()) r.fail(sc, k + ".script", "expected a list of [t_s, depth_mm]");
    for (size_t i = 0; i < sc.size(); ++i) {
      const std::string ki = k + ".script[" + std::to_string(i) + "]";
      if (!sc[i].IsSequence() || sc[i].size() != 2) r.fail(sc[i], ki, "expected [t_s, depth_mm]");
      NeedleScriptPoint p;
      p.t = r.non_negative(sc[i][0], ki);
      p.depth = r.non_negative(sc[i][1], ki) * kMm;
      if (i > 0 && !(p.t > s.script.back().t)) r.fail(sc[i], ki, "times must increase strictly");
      s.script.push_back(p);
    }
  }
  if (const YAML::Node sd = v["seeds_mm"]) {
    if (!sd.IsSequence()) r.fail(sd, k + ".seeds_mm", "expected a list of depths [mm]");
    for (size_t i = 0; i < sd.size(); ++i)
      s.seed_depths.push_back(r.positive(sd[i], k + ".seeds_mm[" + std::to_string(i) + "]") * kMm);
  }
  if (const YAML::Node g = v["gun"]) {
    const std::string kg = k + ".gun";
    r.only_keys(g, kg, {"fire_s", "stroke_mm", "duration_ms", "settle_ms", "notch_offset_mm", "notch_length_mm", "notch_radius_mm"});
    BiopsyGunSpec gun = s.gun ? *s.gun : BiopsyGunSpec{};
    // no fire_s: the gun is armed and fires on a live command (FireGun) only
    gun.fire_time = g["fire_s"] ? r.non_negative(g["fire_s"], kg + ".fire_s") : NAN;
    if (g["stroke_mm"]) gun.stroke = r.positive(g["stroke_mm"], kg + ".stroke_mm") * kMm;
    if (g["duration_ms"]) gun.duration = r.positive(g["duration_ms"], kg + ".duration_ms") * 1e-3;
    if (g["settle_ms"]) gun.settle = r.non_negative(g["settle_ms"], kg + ".settle_ms") * 1e-3;
    if (g["notch_offset_mm"]) gun.notch_offset = r.non_negative(g["notch_offset_mm"], kg + ".notch_offset_mm") * kMm;
    if (g["notch_length_mm"]) gun.notch_length = r.positive(g["notch_length_mm"], kg + ".notch_length_mm") * kMm;
    if (g["notch_radius_mm"]) gun.notch_radius = r.positive(g["notch_radius_mm"], kg + ".notch_radius_mm") * kMm;
    s.gun = gun;
  }
  if (const YAML::Node tc = v["tumour"]) {
    if (!tc.IsSequence()) r.fail(tc, k + ".tumour", "expected a list of component or tag names");
    for (size_t i = 0; i < tc.size(); ++i) s.tumour.push_back(r.string(tc[i], k + ".tumour[" + std::to_string(i) + "]"));
  }
  if (v["target_mm"]) s.target = r.vec3(v["target_mm"], k + ".target_mm", kMm);
  if (v["planned_site"]) s.planned_site = r.string(v["planned_site"], k + ".planned_site");
  if (const YAML::Node ps = v["planned_sites"]) {
    const std::string kp = k + ".planned_sites";
    if (ps.IsScalar()) {
      const std::string scheme = r.string(ps, kp);
      if (scheme != "12-core") r.fail(ps, kp, "unknown scheme '" + scheme + "' (12-core, or a list of sites)");
      s.planned_sites = twelve_core_sites();
    } else if (ps.IsSequence()) {
      for (size_t i = 0; i < ps.size(); ++i) s.planned_sites.push_back(r.string(ps[i], kp + "[" + std::to_string(i) + "]"));
    } else {
      r.fail(ps, kp, "expected 12-core or a list of sites");
    }
    if (!s.gun) r.fail(ps, kp, "planned core sites need a biopsy gun");
  }
  validate_needle_spec(s);
  return s;
}

}  // namespace

namespace {

// The needles of a seed implant plan (`prostatesim plan`, engine/dosimetry/plan.h) as scripted
// brachytherapy needles, one after another: each starts 4 mm in front of its template hole, goes
// in at kPlanSpeed to its deepest seed, rests 0.2 s, and is drawn back out at kPlanSpeed while its
// seeds drop at their planned depths (loose seeds, the stylet held).
constexpr double kPlanSpeed = 0.025;  // [m/s]
constexpr double kPlanStandoff = 0.004;  // [m]

void plan_needles(const std::string& scenario_file, const YamlReader& sr, const YAML::Node& at, NeedleSetSpec& set) {
  const std::string rel = sr.string(at, "needles.plan");
  const std::filesystem::path path = std::filesystem::path(scenario_file).parent_path() / rel;
  std::ifstream f(path, std::ios::binary);
  if (!f) sr.fail(at, "needles.plan", "cannot read the plan file " + path.string());
  std::ostringstream ss;
  ss << f.rdbuf();
  const YamlReader r(path.string());
  YAML::Node root;
  try {
    root = YAML::Load(ss.str());
  } catch (const YAML::Exception& e) {
    throw InputError(path.string(), static_cast<int>(e.mark.line) + 1, "plan", std::string("not valid YAML: ") + e.msg);
  }
  const YAML::Node plan = r.require(root, "", "plan");
  const YAML::Node list = r.require(plan, "plan", "needles");
  if (!list.IsSequence() || list.size() == 0) r.fail(list, "plan.needles", "expected a non-empty list of needles");
  double t = 0.3;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node v = list[i];
    const std::string k = "plan.needles[" + std::to_string(i) + "]";
    NeedleSpec s;
    s.file = path.string();
    s.line = YamlReader::line_of(v);
    s.key = k;
    apply_needle_preset("brachy_18g", s);
    s.preset = "brachy_18g";
    s.name = r.string(r.require(v, k, "hole"), k + ".hole");
    s.direction = r.unit_vec3(r.require(v, k, "direction"), k + ".direction");
    s.start = r.vec3(r.require(v, k, "entry_mm"), k + ".entry_mm", kMm) - kPlanStandoff * s.direction;
    const double depth = r.positive(r.require(v, k, "depth_mm"), k + ".depth_mm") * kMm + kPlanStandoff;
    const YAML::Node sd = r.require(v, k, "seeds_mm");
    if (!sd.IsSequence() || sd.size() == 0) r.fail(sd, k + ".seeds_mm", "expected a non-empty list of depths [mm]");
    for (size_t j = 0; j < sd.size(); ++j) {
      const double d = r.positive(sd[j], k + ".seeds_mm[" + std::to_string(j) + "]") * kMm + kPlanStandoff;
      if (d > depth + 1e-9) r.fail(sd[j], k + ".seeds_mm[" + std::to_string(j) + "]", "deeper than the needle's depth_mm");
      s.seed_depths.push_back(d);
    }
    const double travel = depth / kPlanSpeed;
    s.script = {{0.0, 0.0}, {t, 0.0}, {t + travel, depth}, {t + travel + 0.2, depth}, {t + 2 * travel + 0.2, 0.0}};
    t += 2 * travel + 0.2 + 0.3;
    for (const NeedleSpec& o : set.needles)
      if (o.name == s.name) r.fail(v, k + ".hole", "a second needle in hole '" + s.name + "'");
    set.needles.push_back(std::move(s));
  }
}

}  // namespace

NeedleSetSpec parse_needles_yaml(const YamlReader& r, const YAML::Node& node) {
  r.only_keys(node, "needles", {"puncture_n", "instruments", "event_capacity", "plan"});
  NeedleSetSpec set;
  set.file = r.file();
  set.line = YamlReader::line_of(node);
  if (const YAML::Node p = node["puncture_n"]) {
    if (!p.IsMap()) r.fail(p, "needles.puncture_n", "expected a mapping component -> puncture force [N]");
    for (auto it = p.begin(); it != p.end(); ++it) {
      const std::string c = it->first.as<std::string>();
      set.puncture.emplace_back(c, r.non_negative(it->second, "needles.puncture_n." + c));
    }
  }
  if (node["event_capacity"]) {
    set.event_capacity = r.integer(node["event_capacity"], "needles.event_capacity");
    if (set.event_capacity < 16 || set.event_capacity > 1000000)
      r.fail(node["event_capacity"], "needles.event_capacity", "must be in 16..1000000");
  }
  if (node["plan"]) {
    plan_needles(r.file(), r, node["plan"], set);
    if (!node["instruments"]) return set;
  }
  const YAML::Node list = r.require(node, "needles", "instruments");
  if (!list.IsSequence() || list.size() == 0) r.fail(list, "needles.instruments", "expected a non-empty list of needles");
  for (size_t i = 0; i < list.size(); ++i) {
    set.needles.push_back(parse_needle(r, list[i], static_cast<int>(i)));
    for (size_t j = 0; j + 1 < set.needles.size(); ++j)
      if (set.needles[j].name == set.needles.back().name)
        r.fail(list[i], "needles.instruments[" + std::to_string(i) + "].name", "duplicate needle name '" + set.needles.back().name + "'");
  }
  return set;
}

}  // namespace ps
