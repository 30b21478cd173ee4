// Scenario file reader. Files are in millimetres, kilopascals and milliseconds where people
// think in them (the key says the unit: spacing_mm, young_kpa, dt_ms); converted to SI here.
#include "engine/scenario/parse_yaml.h"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "engine/model/role.h"
#include "engine/scenario/material_models.h"
#include "engine/spec/yaml_reader.h"
#include "engine/tools/tool_kind.h"

namespace ps {

namespace {

constexpr double kMm = 1e-3;   // mm -> m
constexpr double kKpa = 1e3;   // kPa -> Pa

// Physical ranges of the material and discretisation keys, in the file's units. Soft tissue is
// 0.1-100 kPa, bone ~2e7 kPa, steel 2e8 kPa; 1e-3 kPa is softer than any tissue. Whether a
// stiff value is affordable is decided later from the stable substep (compile_time_step.cpp).
constexpr double kMinYoungKpa = 1e-3, kMaxYoungKpa = 1e9;  // [kPa]
constexpr double kMaxStiffnessNm = 1e9;                    // raw k_e / k_s [N/m]
constexpr double kMaxDamping = 1e6;                        // [1/s]
constexpr double kMaxNeedleWeightN = 1e3;                  // k_c, k_f [N]
constexpr double kMinSpacingMm = 0.01, kMaxSpacingMm = 1e4;  // [mm]; the particle count is checked in compile

SourceLoc loc_of(const YamlReader& r, const YAML::Node& n) { return SourceLoc{r.file(), YamlReader::line_of(n)}; }

uint8_t parse_axes(const YamlReader& r, const YAML::Node& v, const std::string& key) {
  const std::string s = r.string(v, key);
  uint8_t mask = 0;
  for (char c : s) {
    if (c == 'x') mask |= 1;
    else if (c == 'y') mask |= 2;
    else if (c == 'z') mask |= 4;
    else r.fail(v, key, "axes must be letters from 'xyz', got '" + s + "'");
  }
  return mask;
}

void parse_ramp(const YamlReader& r, const YAML::Node& v, const std::string& key, double& t0, double& t1) {
  if (!v.IsSequence() || v.size() != 2) r.fail(v, key, "expected [start_s, end_s]");
  t0 = r.non_negative(v[0], key);
  t1 = r.non_negative(v[1], key);
  if (t1 < t0) r.fail(v, key, "ramp end is before its start");
}

RegionSpec parse_region(const YamlReader& r, const YAML::Node& v, const std::string& key) {
  RegionSpec reg;
  if (v.IsScalar() && v.Scalar() == "all") return reg;
  r.only_keys(v, key, {"box", "sphere", "half_space", "ellipsoid"});
  if (v.size() != 1) r.fail(v, key, "a region is exactly one of box, sphere, half_space, ellipsoid or 'all'");
  if (v["box"]) {
    const YAML::Node b = v["box"];
    const std::string k = key + ".box";
    r.only_keys(b, k, {"min_mm", "max_mm"});
    reg.kind = RegionSpec::Box;
    reg.min = r.vec3(r.require(b, k, "min_mm"), k + ".min_mm", kMm);
    reg.max = r.vec3(r.require(b, k, "max_mm"), k + ".max_mm", kMm);
    for (int a = 0; a < 3; ++a)
      if (reg.max[a] < reg.min[a]) r.fail(b, k, "max_mm is below min_mm on an axis");
  } else if (v["sphere"]) {
    const YAML::Node s = v["sphere"];
    const std::string k = key + ".sphere";
    r.only_keys(s, k, {"center_mm", "radius_mm"});
    reg.kind = RegionSpec::Sphere;
    reg.center = r.vec3(r.require(s, k, "center_mm"), k + ".center_mm", kMm);
    reg.radius = r.positive(r.require(s, k, "radius_mm"), k + ".radius_mm") * kMm;
  } else if (v["ellipsoid"]) {
    const YAML::Node e = v["ellipsoid"];
    const std::string k = key + ".ellipsoid";
    r.only_keys(e, k, {"center_mm", "radii_mm"});
    reg.kind = RegionSpec::Ellipsoid;
    reg.center = r.vec3(r.require(e, k, "center_mm"), k + ".center_mm", kMm);
    reg.radii = r.vec3(r.require(e, k, "radii_mm"), k + ".radii_mm", kMm);
    if (!(reg.radii.minCoeff() > 0.0)) r.fail(e["radii_mm"], k + ".radii_mm", "every semi-axis must be positive");
  } else {
    const YAML::Node h = v["half_space"];
    const std::string k = key + ".half_space";
    r.only_keys(h, k, {"point_mm", "normal"});
    reg.kind = RegionSpec::HalfSpace;
    reg.point = r.vec3(r.require(h, k, "point_mm"), k + ".point_mm", kMm);
    reg.normal = r.unit_vec3(r.require(h, k, "normal"), k + ".normal");
  }
  return reg;
}

MaterialSpec parse_material(const YamlReader& r, const std::string& name, const YAML::Node& v) {
  const std::string k = "materials." + name;
  r.only_keys(v, k, {"young_kpa", "k_e_n_m", "density_kg_m3", "damping_1_s", "incompressible", "k_c_n", "k_f_n",
                     "model", "poisson", "k_s_n_m", "thickness_mm", "pressure"});
  MaterialSpec m;
  m.name = name;
  m.loc = loc_of(r, v);
  if (v["young_kpa"]) m.young = r.ranged(v["young_kpa"], k + ".young_kpa", kMinYoungKpa, kMaxYoungKpa, "kPa") * kKpa;
  if (v["k_e_n_m"]) m.k_e = r.ranged(v["k_e_n_m"], k + ".k_e_n_m", 1e-6, kMaxStiffnessNm, "N/m");
  if (!m.young && !m.k_e && !v["k_s_n_m"]) r.fail(v, k, "give young_kpa (Young's modulus) or k_e_n_m (raw stiffness)");
  if (v["density_kg_m3"]) m.density = r.ranged(v["density_kg_m3"], k + ".density_kg_m3", 1.0, 1e5, "kg/m^3");
  if (v["damping_1_s"]) m.damping = r.ranged(v["damping_1_s"], k + ".damping_1_s", 0.0, kMaxDamping, "1/s");
  if (v["incompressible"]) m.incompressible = r.boolean(v["incompressible"], k + ".incompressible");
  if (v["k_c_n"]) m.k_c = r.ranged(v["k_c_n"], k + ".k_c_n", 0.0, kMaxNeedleWeightN, "N");
  if (v["k_f_n"]) m.k_f = r.ranged(v["k_f_n"], k + ".k_f_n", 0.0, kMaxNeedleWeightN, "N");
  if (v["model"]) {
    const std::string model = r.string(v["model"], k + ".model");
    const MaterialModelDesc* desc = find_material_model(model);
    if (!desc) r.fail(v["model"], k + ".model", "model must be paper, strain, tet or shell");
    m.model = desc->model;
  }
  if (v["poisson"]) {
    if (m.model == MaterialModel::Paper)
      r.fail(v["poisson"], k + ".poisson", "poisson only applies to model: strain, tet or shell");
    m.poisson = r.non_negative(v["poisson"], k + ".poisson");
    if (!(*m.poisson < 0.5)) r.fail(v["poisson"], k + ".poisson", "must be in [0, 0.5)");
  }
  if (v["k_s_n_m"]) {
    if (m.model != MaterialModel::Strain) r.fail(v["k_s_n_m"], k + ".k_s_n_m", "k_s_n_m only applies to model: strain");
    m.k_s = r.ranged(v["k_s_n_m"], k + ".k_s_n_m", 1e-6, kMaxStiffnessNm, "N/m");
  }
  if (m.model == MaterialModel::Tet && !m.young) r.fail(v, k, "model: tet needs young_kpa");
  if (v["pressure"]) {
    if (m.model != MaterialModel::Tet) r.fail(v["pressure"], k + ".pressure", "pressure only applies to model: tet");
    const std::string how = r.string(v["pressure"], k + ".pressure");
    if (how == "implicit") m.implicit_pressure = true;
    else if (how != "explicit") r.fail(v["pressure"], k + ".pressure", "must be explicit or implicit");
  }
  if (v["thickness_mm"]) {
    if (m.model != MaterialModel::Shell) r.fail(v["thickness_mm"], k + ".thickness_mm", "thickness_mm only applies to model: shell");
    m.thickness = r.ranged(v["thickness_mm"], k + ".thickness_mm", 0.05, 50.0, "mm") * 1e-3;
  }
  if (m.model == MaterialModel::Shell && !m.young) r.fail(v, k, "model: shell needs young_kpa");
  if (m.model == MaterialModel::Shell && !m.thickness) r.fail(v, k, "model: shell needs thickness_mm (the wall thickness)");
  if (m.model == MaterialModel::Strain && !m.young && !m.k_s)
    r.fail(v, k, "model: strain needs young_kpa or k_s_n_m");
  return m;
}

ShapeSpec parse_shape(const YamlReader& r, const YAML::Node& c, const std::string& k, const std::string& dir) {
  ShapeSpec s;
  const int count = (c["box"] ? 1 : 0) + (c["cylinder"] ? 1 : 0) + (c["mesh"] ? 1 : 0);
  if (count != 1) r.fail(c, k, "a component needs exactly one shape: box, cylinder or mesh");
  if (c["box"]) {
    const YAML::Node b = c["box"];
    const std::string kb = k + ".box";
    r.only_keys(b, kb, {"min_mm", "max_mm"});
    s.kind = ShapeSpec::Box;
    s.min = r.vec3(r.require(b, kb, "min_mm"), kb + ".min_mm", kMm);
    s.max = r.vec3(r.require(b, kb, "max_mm"), kb + ".max_mm", kMm);
    for (int a = 0; a < 3; ++a)
      if (!(s.max[a] > s.min[a])) r.fail(b, kb, "box must have max_mm > min_mm on every axis");
  } else if (c["cylinder"]) {
    const YAML::Node y = c["cylinder"];
    const std::string ky = k + ".cylinder";
    r.only_keys(y, ky, {"base_mm", "axis", "radius_mm", "length_mm"});
    s.kind = ShapeSpec::Cylinder;
    s.base = y["base_mm"] ? r.vec3(y["base_mm"], ky + ".base_mm", kMm) : Vec3::Zero();
    s.axis = y["axis"] ? r.unit_vec3(y["axis"], ky + ".axis") : Vec3::UnitZ();
    s.radius = r.positive(r.require(y, ky, "radius_mm"), ky + ".radius_mm") * kMm;
    s.length = r.positive(r.require(y, ky, "length_mm"), ky + ".length_mm") * kMm;
  } else {
    const YAML::Node me = c["mesh"];
    const std::string km = k + ".mesh";
    r.only_keys(me, km, {"file", "units", "translate_mm", "rotate_deg", "scale"});
    s.kind = ShapeSpec::Mesh;
    std::filesystem::path p = r.string(r.require(me, km, "file"), km + ".file");
    if (p.is_relative()) p = std::filesystem::path(dir) / p;
    s.mesh.file = p.lexically_normal().string();
    const std::string units = me["units"] ? r.string(me["units"], km + ".units") : "mm";
    if (units == "mm") s.mesh.unit_scale = 1e-3;
    else if (units == "cm") s.mesh.unit_scale = 1e-2;
    else if (units == "dm") s.mesh.unit_scale = 1e-1;
    else if (units == "m") s.mesh.unit_scale = 1.0;
    else r.fail(me["units"], km + ".units", "units must be mm, cm, dm or m");
    if (me["translate_mm"]) s.mesh.translate = r.vec3(me["translate_mm"], km + ".translate_mm", kMm);
    if (me["rotate_deg"]) s.mesh.rotate_deg = r.vec3(me["rotate_deg"], km + ".rotate_deg");
    if (me["scale"]) {
      if (me["scale"].IsSequence()) s.mesh.scale = r.vec3(me["scale"], km + ".scale");
      else s.mesh.scale = Vec3::Constant(r.positive(me["scale"], km + ".scale"));
      if (!(s.mesh.scale.minCoeff() > 0)) r.fail(me["scale"], km + ".scale", "scale must be positive");
    }
  }
  return s;
}

// A `role:` value: one of the words of engine/model/role.h, kept as written.
std::string parse_role_word(const YamlReader& r, const YAML::Node& v, const std::string& k) {
  const std::string w = r.string(v, k);
  Role role = Role::Other;
  if (!parse_role(w, &role)) r.fail(v, k, "unknown role '" + w + "' (" + role_words() + ")");
  return w;
}

ComponentSpec parse_component(const YamlReader& r, const YAML::Node& c, int index, const std::string& dir) {
  const std::string k = "components[" + std::to_string(index) + "]";
  r.only_keys(c, k, {"name", "role", "type", "material", "spacing_mm", "fill", "box", "cylinder", "mesh", "kinematic",
                     "fibre", "active_stress_kpa", "activation", "exclude_inside"});
  ComponentSpec cs;
  cs.loc = loc_of(r, c);
  cs.name = r.string(r.require(c, k, "name"), k + ".name");
  if (c["role"]) cs.role = parse_role_word(r, c["role"], k + ".role");
  if (c["type"]) {
    cs.kind = r.string(c["type"], k + ".type");
    if (cs.kind != "elastic" && cs.kind != "rigid" && cs.kind != "active")
      r.fail(c["type"], k + ".type", "type must be elastic, rigid or active");
  }
  cs.material = r.string(r.require(c, k, "material"), k + ".material");
  cs.spacing = r.ranged(r.require(c, k, "spacing_mm"), k + ".spacing_mm", kMinSpacingMm, kMaxSpacingMm, "mm") * kMm;
  if (c["fill"]) {
    const std::string f = r.string(c["fill"], k + ".fill");
    if (f == "volumetric") cs.volumetric = true;
    else if (f == "surface") cs.volumetric = false;
    else r.fail(c["fill"], k + ".fill", "fill must be volumetric or surface");
  }
  cs.shape = parse_shape(r, c, k, dir);
  if (c["exclude_inside"]) {
    const YAML::Node ex = c["exclude_inside"];
    if (!ex.IsSequence()) r.fail(ex, k + ".exclude_inside", "expected a list of component names");
    if (!cs.volumetric) r.fail(ex, k + ".exclude_inside", "only a volumetric component can exclude others");
    for (size_t i = 0; i < ex.size(); ++i) cs.exclude_inside.push_back(r.string(ex[i], k + ".exclude_inside"));
  }
  if (c["kinematic"]) {
    if (cs.kind != "rigid") r.fail(c["kinematic"], k + ".kinematic", "only rigid components are kinematic");
    cs.kinematic = r.boolean(c["kinematic"], k + ".kinematic");
  }
  const bool any_active = c["fibre"] || c["active_stress_kpa"] || c["activation"];
  if (any_active && cs.kind != "active")
    r.fail(c, k, "fibre / active_stress_kpa / activation only apply to type: active");
  if (cs.kind == "active") {
    cs.fibre = r.unit_vec3(r.require(c, k, "fibre"), k + ".fibre");
    cs.active_stress = r.ranged(r.require(c, k, "active_stress_kpa"), k + ".active_stress_kpa", 0.0, 1e4, "kPa") * kKpa;
    if (c["activation"]) {
      cs.activation = r.number(c["activation"], k + ".activation");
      if (cs.activation < 0.0 || cs.activation > 1.0) r.fail(c["activation"], k + ".activation", "must be in [0, 1]");
    }
  }
  return cs;
}

ConstraintSpec parse_constraint(const YamlReader& r, const YAML::Node& c, int index) {
  const std::string k = "constraints[" + std::to_string(index) + "]";
  r.only_keys(c, k, {"fix", "displace", "half_space", "force"});
  if (c.size() != 1) r.fail(c, k, "each constraint is exactly one of fix, displace, half_space, force");
  ConstraintSpec cs;
  cs.loc = loc_of(r, c);
  const std::string kind = c.begin()->first.as<std::string>();
  const YAML::Node v = c.begin()->second;
  const std::string kk = k + "." + kind;
  if (kind == "fix") {
    cs.kind = ConstraintSpec::Fix;
    r.only_keys(v, kk, {"component", "region", "axes"});
  } else if (kind == "displace") {
    cs.kind = ConstraintSpec::Displace;
    r.only_keys(v, kk, {"component", "region", "axes", "by_mm", "ramp_s"});
    cs.by = r.vec3(r.require(v, kk, "by_mm"), kk + ".by_mm", kMm);
    parse_ramp(r, r.require(v, kk, "ramp_s"), kk + ".ramp_s", cs.t0, cs.t1);
  } else if (kind == "half_space") {
    cs.kind = ConstraintSpec::HalfSpace;
    r.only_keys(v, kk, {"component", "point_mm", "normal"});
    cs.region.kind = RegionSpec::HalfSpace;
    cs.region.point = r.vec3(r.require(v, kk, "point_mm"), kk + ".point_mm", kMm);
    cs.region.normal = r.unit_vec3(r.require(v, kk, "normal"), kk + ".normal");
  } else {
    cs.kind = ConstraintSpec::Force;
    r.only_keys(v, kk, {"component", "region", "total_n", "ramp_s"});
    cs.by = r.vec3(r.require(v, kk, "total_n"), kk + ".total_n");
    if (v["ramp_s"]) parse_ramp(r, v["ramp_s"], kk + ".ramp_s", cs.t0, cs.t1);
  }
  if (v["component"]) cs.component = r.string(v["component"], kk + ".component");
  if (cs.kind != ConstraintSpec::HalfSpace) cs.region = parse_region(r, r.require(v, kk, "region"), kk + ".region");
  if (v["axes"]) cs.axes = parse_axes(r, v["axes"], kk + ".axes");
  if (cs.axes == 0) r.fail(v["axes"], kk + ".axes", "no axis selected");
  return cs;
}

OverrideSpec parse_override(const YamlReader& r, const YAML::Node& v, int index) {
  const std::string k = "overrides[" + std::to_string(index) + "]";
  r.only_keys(v, k, {"component", "region", "young_kpa", "k_e_n_m", "k_c_n", "k_f_n", "damping_1_s"});
  OverrideSpec o;
  o.loc = loc_of(r, v);
  o.component = r.string(r.require(v, k, "component"), k + ".component");
  o.region = parse_region(r, r.require(v, k, "region"), k + ".region");
  if (v["young_kpa"]) o.young = r.ranged(v["young_kpa"], k + ".young_kpa", kMinYoungKpa, kMaxYoungKpa, "kPa") * kKpa;
  if (v["k_e_n_m"]) o.k_e = r.ranged(v["k_e_n_m"], k + ".k_e_n_m", 1e-6, kMaxStiffnessNm, "N/m");
  if (v["k_c_n"]) o.k_c = r.ranged(v["k_c_n"], k + ".k_c_n", 0.0, kMaxNeedleWeightN, "N");
  if (v["k_f_n"]) o.k_f = r.ranged(v["k_f_n"], k + ".k_f_n", 0.0, kMaxNeedleWeightN, "N");
  if (v["damping_1_s"]) o.damping = r.ranged(v["damping_1_s"], k + ".damping_1_s", 0.0, kMaxDamping, "1/s");
  if (!o.young && !o.k_e && !o.k_c && !o.k_f && !o.damping) r.fail(v, k, "an override must set at least one parameter");
  return o;
}

}  // namespace

namespace {
ScenarioSpec parse_scenario_impl(const std::string& text, const std::string& path) {
  const YamlReader r(path);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(path, static_cast<int>(e.mark.line) + 1, "", "YAML syntax error: " + e.msg);
  }
  if (!root.IsMap()) throw InputError(path, 1, "", "a scenario file is a YAML mapping (name:, components:, ...)");
  std::vector<std::string> keys = {"name",  "solver", "time", "gravity_m_s2", "rest", "watchdog", "materials", "components", "constraints",
                                   "overrides", "links", "tags", "prostate_zones", "lesions"};
  for (const ToolKind* k : tool_kinds()) keys.push_back(k->key);  // each instrument's section
  r.only_keys(root, "", keys);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  ScenarioSpec s;
  s.file = path;
  s.name = r.string(r.require(root, "", "name"), "name");
  if (root["time"]) {
    const YAML::Node t = root["time"];
    r.only_keys(t, "time", {"dt_ms", "substeps", "duration_s"});
    if (t["dt_ms"]) s.dt = r.ranged(t["dt_ms"], "time.dt_ms", 1e-4, 100.0, "ms") * 1e-3;
    if (t["substeps"]) {
      s.substeps = r.integer(t["substeps"], "time.substeps");
      if (s.substeps < 1 || s.substeps > 100000) r.fail(t["substeps"], "time.substeps", "must be in 1..100000");
    }
    if (t["duration_s"]) s.duration = r.ranged(t["duration_s"], "time.duration_s", 1e-6, ScenarioSpec::kMaxDuration, "s");
  }
  if (root["solver"]) {
    const YAML::Node t = root["solver"];
    r.only_keys(t, "solver", {"redistribution", "triplets", "mass_scaling", "multirate", "multirate_inertia", "pressure_iterations", "sleep",
                          "sleep_wake_m_s2", "stiffness_damping_s"});
    if (t["mass_scaling"]) s.mass_scaling = r.boolean(t["mass_scaling"], "solver.mass_scaling");
    if (t["multirate"]) s.multirate = r.boolean(t["multirate"], "solver.multirate");
    if (t["multirate_inertia"]) {
      s.multirate_inertia = r.ranged(t["multirate_inertia"], "solver.multirate_inertia", 1.0, 16.0, "x own mass");
      if (!s.multirate && s.multirate_inertia > 1.0)
        r.fail(t["multirate_inertia"], "solver.multirate_inertia", "needs solver.multirate: true");
    }
    if (t["sleep"]) s.sleep = r.boolean(t["sleep"], "solver.sleep");
    if (t["sleep_wake_m_s2"]) s.sleep_wake_accel = r.ranged(t["sleep_wake_m_s2"], "solver.sleep_wake_m_s2", 1e-3, 100.0, "m/s^2");
    if (s.sleep && s.multirate) r.fail(t["sleep"], "solver.sleep", "cannot be combined with solver.multirate (both choose which tet elements run)");
    // beta above 1 ms would damp the organ-scale motion itself (zeta = beta omega / 2 is 0.02 at
    // 40 rad/s) and shrink the stable substep below what any scene here could afford
    if (t["stiffness_damping_s"])
      s.stiffness_damping = r.ranged(t["stiffness_damping_s"], "solver.stiffness_damping_s", 0.0, 1e-3, "s");
    if (t["pressure_iterations"]) {
      s.pressure_iterations = r.integer(t["pressure_iterations"], "solver.pressure_iterations");
      if (s.pressure_iterations < 1 || s.pressure_iterations > 8)
        r.fail(t["pressure_iterations"], "solver.pressure_iterations", "must be in 1..8");
    }
    if (t["triplets"]) {
      if (t["triplets"].IsScalar() && t["triplets"].Scalar() == "all") s.max_triplets = 0;
      else {
        s.max_triplets = r.integer(t["triplets"], "solver.triplets");
        if (s.max_triplets < 1 || s.max_triplets > 560)
          r.fail(t["triplets"], "solver.triplets", "must be all or a count in 1..560");
      }
    }
    if (t["redistribution"]) {
      const std::string v = r.string(t["redistribution"], "solver.redistribution");
      if (v == "linear") s.linear_redistribution = true;
      else if (v != "gradient") r.fail(t["redistribution"], "solver.redistribution", "must be gradient or linear");
    }
  }
  if (root["gravity_m_s2"]) {
    s.gravity = r.vec3(root["gravity_m_s2"], "gravity_m_s2");
    if (s.gravity.norm() > 1000.0) r.fail(root["gravity_m_s2"], "gravity_m_s2", "out of physical range: |g| above 1000 m/s^2");
  }
  if (root["rest"]) {
    const YAML::Node t = root["rest"];
    r.only_keys(t, "rest", {"kinetic_energy_j", "hold_s"});
    if (t["kinetic_energy_j"]) s.rest_kinetic_energy = r.ranged(t["kinetic_energy_j"], "rest.kinetic_energy_j", 1e-15, 1e3, "J");
    if (t["hold_s"]) s.rest_hold = r.non_negative(t["hold_s"], "rest.hold_s");
  }
  if (root["watchdog"]) {
    const YAML::Node w = root["watchdog"];
    r.only_keys(w, "watchdog", {"leave_margin_mm"});
    if (w["leave_margin_mm"]) s.leave_margin = r.ranged(w["leave_margin_mm"], "watchdog.leave_margin_mm", 1.0, 10000.0, "mm") * 1e-3;
  }
  const YAML::Node mats = r.require(root, "", "materials");
  if (!mats.IsMap() || mats.size() == 0) r.fail(mats, "materials", "expected a non-empty mapping name -> material");
  for (auto it = mats.begin(); it != mats.end(); ++it)
    s.materials.push_back(parse_material(r, it->first.as<std::string>(), it->second));
  const YAML::Node comps = r.require(root, "", "components");
  if (!comps.IsSequence() || comps.size() == 0) r.fail(comps, "components", "expected a non-empty list");
  for (size_t i = 0; i < comps.size(); ++i) s.components.push_back(parse_component(r, comps[i], static_cast<int>(i), dir));
  auto list = [&](const char* key) {
    const YAML::Node n = root[key];
    if (n && !n.IsSequence()) r.fail(n, key, "expected a list");
    return n;
  };
  if (const YAML::Node n = list("constraints"))
    for (size_t i = 0; i < n.size(); ++i) s.constraints.push_back(parse_constraint(r, n[i], static_cast<int>(i)));
  if (const YAML::Node n = list("overrides"))
    for (size_t i = 0; i < n.size(); ++i) s.overrides.push_back(parse_override(r, n[i], static_cast<int>(i)));
  if (const YAML::Node n = list("links"))
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string k = "links[" + std::to_string(i) + "]";
      r.only_keys(n[i], k, {"a", "b", "distance_mm"});
      LinkSpec l;
      l.loc = loc_of(r, n[i]);
      l.a = r.string(r.require(n[i], k, "a"), k + ".a");
      l.b = r.string(r.require(n[i], k, "b"), k + ".b");
      l.distance = r.ranged(r.require(n[i], k, "distance_mm"), k + ".distance_mm", 1e-3, 1e3, "mm") * kMm;
      s.links.push_back(l);
    }
  if (const YAML::Node n = list("tags"))
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string k = "tags[" + std::to_string(i) + "]";
      r.only_keys(n[i], k, {"name", "role", "component", "region"});
      TagSpec t;
      t.loc = loc_of(r, n[i]);
      t.name = r.string(r.require(n[i], k, "name"), k + ".name");
      if (n[i]["role"]) t.role = parse_role_word(r, n[i]["role"], k + ".role");
      t.component = r.string(r.require(n[i], k, "component"), k + ".component");
      t.region = parse_region(r, r.require(n[i], k, "region"), k + ".region");
      s.tags.push_back(t);
    }
  if (const YAML::Node z = root["prostate_zones"]) {
    r.only_keys(z, "prostate_zones", {"component", "peripheral_depth_mm"});
    ZonesSpec zs;
    zs.loc = loc_of(r, z);
    zs.component = r.string(r.require(z, "prostate_zones", "component"), "prostate_zones.component");
    if (z["peripheral_depth_mm"])
      zs.peripheral_depth = r.ranged(z["peripheral_depth_mm"], "prostate_zones.peripheral_depth_mm", 1e-3, 100.0, "mm") * kMm;
    s.prostate_zones = zs;
  }
  if (const YAML::Node l = root["lesions"]) {
    r.only_keys(l, "lesions", {"count", "seed", "zone", "diameter_mm"});
    if (!s.prostate_zones) r.fail(l, "lesions", "lesions are placed in a prostate zone: give prostate_zones first");
    LesionsSpec ls;
    ls.loc = loc_of(r, l);
    if (l["count"]) {
      ls.count = r.integer(l["count"], "lesions.count");
      if (ls.count < 1 || ls.count > 8) r.fail(l["count"], "lesions.count", "must be 1..8");
    }
    if (l["seed"]) {
      const int seed = r.integer(l["seed"], "lesions.seed");
      if (seed < 0) r.fail(l["seed"], "lesions.seed", "must be >= 0");
      ls.seed = static_cast<uint64_t>(seed);
    }
    if (l["zone"]) {
      ls.zone = r.string(l["zone"], "lesions.zone");
      if (ls.zone != "peripheral" && ls.zone != "transition" && ls.zone != "anterior")
        r.fail(l["zone"], "lesions.zone", "unknown zone '" + ls.zone + "' (peripheral, transition, anterior)");
    }
    if (l["diameter_mm"]) ls.diameter = r.ranged(l["diameter_mm"], "lesions.diameter_mm", 2.0, 40.0, "mm") * kMm;
    s.lesions = ls;
  }
  for (const ToolKind* k : tool_kinds())  // each instrument kind parses its own section
    if (root[k->key]) k->parse_section(r, root[k->key], s);
  finish_tool_specs(s);  // e.g. needles in the probe's guide start on it

  // cross references, checked here so errors point at the line that names them
  auto has_material = [&](const std::string& m) {
    for (const auto& x : s.materials) if (x.name == m) return true;
    return false;
  };
  auto has_component = [&](const std::string& c) {
    for (const auto& x : s.components) if (x.name == c) return true;
    return false;
  };
  for (size_t i = 0; i < s.components.size(); ++i) {
    const auto& c = s.components[i];
    if (!has_material(c.material))
      throw InputError(path, c.loc.line, "components[" + std::to_string(i) + "].material", "unknown material '" + c.material + "'");
    for (size_t j = 0; j < i; ++j)
      if (s.components[j].name == c.name)
        throw InputError(path, c.loc.line, "components[" + std::to_string(i) + "].name", "duplicate component name '" + c.name + "'");
  }
  for (size_t i = 0; i < s.constraints.size(); ++i)
    if (!s.constraints[i].component.empty() && !has_component(s.constraints[i].component))
      throw InputError(path, s.constraints[i].loc.line, "constraints[" + std::to_string(i) + "].component",
                       "unknown component '" + s.constraints[i].component + "'");
  for (size_t i = 0; i < s.overrides.size(); ++i)
    if (!has_component(s.overrides[i].component))
      throw InputError(path, s.overrides[i].loc.line, "overrides[" + std::to_string(i) + "].component",
                       "unknown component '" + s.overrides[i].component + "'");
  for (size_t i = 0; i < s.components.size(); ++i)
    for (const std::string& e : s.components[i].exclude_inside) {
      const std::string k = "components[" + std::to_string(i) + "].exclude_inside";
      if (!has_component(e)) throw InputError(path, s.components[i].loc.line, k, "unknown component '" + e + "'");
      if (e == s.components[i].name) throw InputError(path, s.components[i].loc.line, k, "a component cannot exclude itself");
      for (const auto& o : s.components)
        if (o.name == e && !o.exclude_inside.empty())
          throw InputError(path, s.components[i].loc.line, k, "'" + e + "' excludes others itself; exclusion does not chain");
    }
  std::set<std::string> tag_names;
  for (size_t i = 0; i < s.tags.size(); ++i) {
    const std::string k = "tags[" + std::to_string(i) + "]";
    if (!has_component(s.tags[i].component))
      throw InputError(path, s.tags[i].loc.line, k + ".component", "unknown component '" + s.tags[i].component + "'");
    if (!tag_names.insert(s.tags[i].name).second)
      throw InputError(path, s.tags[i].loc.line, k + ".name", "duplicate tag name '" + s.tags[i].name + "'");
  }
  if (s.prostate_zones && !has_component(s.prostate_zones->component))
    throw InputError(path, s.prostate_zones->loc.line, "prostate_zones.component",
                     "unknown component '" + s.prostate_zones->component + "'");
  for (size_t i = 0; i < s.links.size(); ++i) {
    const auto& l = s.links[i];
    for (const std::string* n : {&l.a, &l.b})
      if (!has_component(*n))
        throw InputError(path, l.loc.line, "links[" + std::to_string(i) + "]", "unknown component '" + *n + "'");
    if (l.a == l.b) throw InputError(path, l.loc.line, "links[" + std::to_string(i) + "]", "a component cannot link to itself");
  }
  return s;
}

}  // namespace

ScenarioSpec parse_scenario_text(const std::string& text, const std::string& path) {
  try {
    return parse_scenario_impl(text, path);
  } catch (const YAML::Exception& e) {
    // A conversion the typed readers did not foresee (found by the fuzz test: a mapping used as a
    // key) is still the file's fault: report it where yaml-cpp points.
    throw InputError(path, e.mark.is_null() ? 0 : static_cast<int>(e.mark.line) + 1, "", "malformed YAML: " + e.msg);
  }
}

ScenarioSpec parse_scenario_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open scenario file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "", "cannot read scenario file");
  return parse_scenario_text(ss.str(), path);
}

bool RegionSpec::contains(const Vec3& x) const {
  switch (kind) {
    case All: return true;
    case Box: return (x.array() >= min.array() - 1e-12).all() && (x.array() <= max.array() + 1e-12).all();
    case Sphere: return (x - center).norm() <= radius + 1e-12;
    case HalfSpace: return (x - point).dot(normal) >= -1e-12;
    case Ellipsoid: return ((x - center).array() / radii.array()).matrix().squaredNorm() <= 1.0 + 1e-12;
  }
  return false;
}

}  // namespace ps
