#include "engine/tools/probe/probe_parse.h"

#include <cmath>
#include <numbers>

namespace ps {

namespace {

constexpr double kMm = 1e-3;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kMaxTiltDeg = 45.0;  // engine/tools/probe/probe.h kProbeMaxTiltRad

SourceLoc loc_of(const YamlReader& r, const YAML::Node& n) { return SourceLoc{r.file(), YamlReader::line_of(n)}; }

double angle(const YamlReader& r, const YAML::Node& v, const std::string& key, bool tilt_like) {
  const double a = r.number(v, key);
  if (!std::isfinite(a)) r.fail(v, key, "not a finite number");
  if (tilt_like && std::abs(a) > kMaxTiltDeg) r.fail(v, key, "must be within +-45 degrees");
  return a * kDeg;
}

void check_component(const YamlReader& r, const ScenarioSpec& s, const YAML::Node& v, const std::string& key,
                     const std::string& name) {
  for (const auto& c : s.components)
    if (c.name == name) return;
  r.fail(v, key, "unknown component '" + name + "'");
}

}  // namespace

void parse_probe_section(const YamlReader& r, const YAML::Node& n, ScenarioSpec& s) {
  r.only_keys(n, "probe", {"radius_mm", "length_mm", "entry_mm", "axis", "anterior", "pose", "moves", "contact", "limits",
                           "needle_guide", "template"});
  ProbeSpec p;
  p.loc = loc_of(r, n);
  if (n["radius_mm"]) p.radius = r.positive(n["radius_mm"], "probe.radius_mm") * kMm;
  if (n["length_mm"]) p.length = r.positive(n["length_mm"], "probe.length_mm") * kMm;
  p.entry = r.vec3(r.require(n, "probe", "entry_mm"), "probe.entry_mm", kMm);
  if (n["axis"]) p.axis = r.unit_vec3(n["axis"], "probe.axis");
  if (n["anterior"]) p.anterior = r.unit_vec3(n["anterior"], "probe.anterior");
  if ((p.anterior - p.anterior.dot(p.axis) * p.axis).norm() < 1e-3)
    r.fail(n["anterior"] ? n["anterior"] : n, "probe.anterior", "must not be parallel to the rectal axis");
  p.anterior = (p.anterior - p.anterior.dot(p.axis) * p.axis).normalized();

  const YAML::Node pose = r.require(n, "probe", "pose");
  r.only_keys(pose, "probe.pose", {"insertion_mm", "offset_mm", "roll_deg", "tilt_deg", "yaw_deg"});
  p.pose_loc = loc_of(r, pose);
  p.pose.insertion = r.number(r.require(pose, "probe.pose", "insertion_mm"), "probe.pose.insertion_mm") * kMm;
  if (!std::isfinite(p.pose.insertion)) r.fail(pose["insertion_mm"], "probe.pose.insertion_mm", "not a finite number");
  if (pose["offset_mm"]) p.pose.offset = r.vec3(pose["offset_mm"], "probe.pose.offset_mm", kMm);
  if (pose["roll_deg"]) p.pose.roll = angle(r, pose["roll_deg"], "probe.pose.roll_deg", false);
  if (pose["tilt_deg"]) p.pose.tilt = angle(r, pose["tilt_deg"], "probe.pose.tilt_deg", true);
  if (pose["yaw_deg"]) p.pose.yaw = angle(r, pose["yaw_deg"], "probe.pose.yaw_deg", true);

  if (const YAML::Node mv = n["moves"]) {
    if (!mv.IsSequence()) r.fail(mv, "probe.moves", "expected a list");
    for (size_t i = 0; i < mv.size(); ++i) {
      const YAML::Node m = mv[i];
      const std::string k = "probe.moves[" + std::to_string(i) + "]";
      r.only_keys(m, k, {"ramp_s", "insertion_mm", "offset_mm", "roll_deg", "tilt_deg", "yaw_deg"});
      ProbeMoveSpec ms;
      ms.loc = loc_of(r, m);
      const YAML::Node ramp = r.require(m, k, "ramp_s");
      if (!ramp.IsSequence() || ramp.size() != 2) r.fail(ramp, k + ".ramp_s", "expected [start_s, end_s]");
      ms.t0 = r.non_negative(ramp[0], k + ".ramp_s");
      ms.t1 = r.non_negative(ramp[1], k + ".ramp_s");
      if (ms.t1 < ms.t0) r.fail(ramp, k + ".ramp_s", "ramp end is before its start");
      if (m["insertion_mm"]) ms.insertion = r.number(m["insertion_mm"], k + ".insertion_mm") * kMm;
      if (ms.insertion && !std::isfinite(*ms.insertion)) r.fail(m["insertion_mm"], k + ".insertion_mm", "not a finite number");
      if (m["offset_mm"]) ms.offset = r.vec3(m["offset_mm"], k + ".offset_mm", kMm);
      if (m["roll_deg"]) ms.roll = angle(r, m["roll_deg"], k + ".roll_deg", false);
      if (m["tilt_deg"]) ms.tilt = angle(r, m["tilt_deg"], k + ".tilt_deg", true);
      if (m["yaw_deg"]) ms.yaw = angle(r, m["yaw_deg"], k + ".yaw_deg", true);
      if (!ms.insertion && !ms.offset && !ms.roll && !ms.tilt && !ms.yaw)
        r.fail(m, k, "a move sets at least one of insertion_mm, offset_mm, roll_deg, tilt_deg, yaw_deg");
      p.moves.push_back(ms);
    }
  }

  if (const YAML::Node c = n["contact"]) {
    r.only_keys(c, "probe.contact", {"mode", "components", "rectum", "prostate", "couple_distance_mm"});
    if (c["mode"]) {
      const std::string mode = r.string(c["mode"], "probe.contact.mode");
      if (mode == "imposed") p.imposed_mode = true;
      else if (mode != "contact") r.fail(c["mode"], "probe.contact.mode", "must be contact (default) or imposed");
    }
    if (const YAML::Node cl = c["components"]) {
      if (!cl.IsSequence() || cl.size() == 0) r.fail(cl, "probe.contact.components", "expected a non-empty list of names");
      for (size_t i = 0; i < cl.size(); ++i) {
        const std::string name = r.string(cl[i], "probe.contact.components");
        check_component(r, s, cl[i], "probe.contact.components", name);
        p.contact_components.push_back(name);
      }
    }
    if (c["rectum"]) {
      p.rectum = r.string(c["rectum"], "probe.contact.rectum");
      check_component(r, s, c["rectum"], "probe.contact.rectum", p.rectum);
    }
    if (c["prostate"]) {
      p.prostate = r.string(c["prostate"], "probe.contact.prostate");
      check_component(r, s, c["prostate"], "probe.contact.prostate", p.prostate);
    }
    if (c["couple_distance_mm"]) p.couple_distance = r.positive(c["couple_distance_mm"], "probe.contact.couple_distance_mm") * kMm;
    if (p.imposed_mode && (p.rectum.empty() || p.prostate.empty()))
      r.fail(c, "probe.contact.mode", "mode imposed needs contact.rectum and contact.prostate");
  }
  if (const YAML::Node l = n["limits"]) {
    r.only_keys(l, "probe.limits", {"max_speed_mm_s", "max_angular_speed_deg_s"});
    if (l["max_speed_mm_s"]) p.max_speed = r.positive(l["max_speed_mm_s"], "probe.limits.max_speed_mm_s") * kMm;
    if (l["max_angular_speed_deg_s"])
      p.max_angular_speed = r.positive(l["max_angular_speed_deg_s"], "probe.limits.max_angular_speed_deg_s") * kDeg;
  }
  if (const YAML::Node g = n["needle_guide"]) {
    p.has_guide = true;
    r.only_keys(g, "probe.needle_guide", {"angle_deg", "back_mm"});
    if (g["angle_deg"]) {
      p.guide_angle = r.number(g["angle_deg"], "probe.needle_guide.angle_deg") * kDeg;
      if (!(p.guide_angle >= 0.0 && p.guide_angle < 90.0 * kDeg))
        r.fail(g["angle_deg"], "probe.needle_guide.angle_deg", "must be in [0, 90) degrees");
    }
    if (g["back_mm"]) p.guide_back = r.non_negative(g["back_mm"], "probe.needle_guide.back_mm") * kMm;
  }
  if (const YAML::Node t = n["template"]) {
    p.has_template = true;
    r.only_keys(t, "probe.template", {"distance_mm", "pitch_mm", "cols", "rows", "first_row_mm"});
    if (t["distance_mm"]) p.template_distance = r.number(t["distance_mm"], "probe.template.distance_mm") * kMm;
    if (t["pitch_mm"]) p.template_pitch = r.positive(t["pitch_mm"], "probe.template.pitch_mm") * kMm;
    auto count = [&](const char* key, int& out) {
      if (!t[key]) return;
      out = r.integer(t[key], std::string("probe.template.") + key);
      if (out < 1 || out > 100) r.fail(t[key], std::string("probe.template.") + key, "must be in 1..100");
    };
    count("cols", p.template_cols);
    count("rows", p.template_rows);
    if (t["first_row_mm"]) p.template_first_row = r.number(t["first_row_mm"], "probe.template.first_row_mm") * kMm;
  }
  s.probe = p;
}

}  // namespace ps
