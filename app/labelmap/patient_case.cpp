#include "app/labelmap/patient_case.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "engine/anatomy/anatomy_files.h"
#include "engine/anatomy/shapes.h"
#include "engine/mesh/mesh_query.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps::labelmap {

namespace {

// Remeshed edge per role [mm]: about the default anatomy's (engine/anatomy), below each
// component's particle spacing in the scenario.
double edge_mm(const std::string& role) {
  if (role == "prostate") return 3.0;
  if (role == "bladder") return 5.0;
  if (role == "rectum") return 4.0;
  if (role == "bone") return 3.5;
  return 10.0;   // fat
}

constexpr double kFatMarginMm = 20.0;     // fat block around the organs when there is no fat label
constexpr double kProbeBelowMm = 32.0;    // probe entry below the prostate centre (config/biopsy.yaml)

std::string values_text(const std::vector<int>& values) {
  std::string s;
  for (int v : values) s += (s.empty() ? "" : "+") + std::to_string(v);
  return s;
}

std::string mm(double m) {
  char buf[32];
  double v = std::round(m * 1e4) / 10.0;
  if (v == 0.0) v = 0.0;
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

std::string mm3(const Vec3& p) { return "[" + mm(p.x()) + ", " + mm(p.y()) + ", " + mm(p.z()) + "]"; }

void bounds(const TriMesh& m, Vec3& lo, Vec3& hi) {
  lo = hi = m.vertices.front();
  for (const Vec3& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
}

const CaseOrgan* find(const PatientCase& c, const std::string& role) {
  for (const auto& o : c.organs)
    if (o.role == role) return &o;
  return nullptr;
}

}  // namespace

const std::vector<std::string>& case_roles() {
  static const std::vector<std::string> roles = {"prostate", "bladder", "rectum", "bone", "fat"};
  return roles;
}

std::vector<OrganLabels> parse_label_list(const std::string& text, const std::string& option) {
  std::vector<OrganLabels> out;
  std::set<int> used;
  std::stringstream ss(text);
  std::string item;
  std::string known;
  for (const auto& r : case_roles()) known += (known.empty() ? "" : ", ") + r;
  while (std::getline(ss, item, ',')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos) throw InputError("", 0, option, "'" + item + "' is not role=label (e.g. prostate=1)");
    OrganLabels o;
    o.role = item.substr(0, eq);
    if (std::find(case_roles().begin(), case_roles().end(), o.role) == case_roles().end())
      throw InputError("", 0, option, "unknown organ '" + o.role + "' (known: " + known + ")");
    for (const auto& x : out)
      if (x.role == o.role) throw InputError("", 0, option, "'" + o.role + "' is given twice");
    std::stringstream vs(item.substr(eq + 1));
    std::string value;
    while (std::getline(vs, value, '+')) {
      size_t used_chars = 0;
      long n = 0;
      try {
        n = std::stol(value, &used_chars);
      } catch (const std::exception&) {
        used_chars = 0;
      }
      if (used_chars != value.size() || value.empty() || n < 1 || n > 2147483647)
        throw InputError("", 0, option, o.role + ": label '" + value + "' is not a positive integer");
      if (!used.insert(static_cast<int>(n)).second)
        throw InputError("", 0, option, o.role + ": label " + value + " is already used by another organ");
      o.values.push_back(static_cast<int>(n));
    }
    if (o.values.empty()) throw InputError("", 0, option, o.role + ": no label value");
    out.push_back(o);
  }
  for (const char* need : {"prostate", "rectum"})
    if (std::none_of(out.begin(), out.end(), [&](const OrganLabels& o) { return o.role == need; }))
      throw InputError("", 0, option, std::string("missing label for '") + need + "' (the case needs prostate and rectum; the probe lies in the rectum)");
  return out;
}

PatientCase make_patient_case(const LabelVolume& volume, const std::vector<OrganLabels>& organs) {
  PatientCase c;
  c.source = std::filesystem::path(volume.file).filename().string();
  // every organ's voxels first, so that an empty one is named before minutes of surfaces
  for (const auto& o : organs)
    if (count_voxels(volume, o.values) == 0)
      throw InputError(volume.file, 0, o.role + " (label " + values_text(o.values) + ")",
                       "no voxel carries this label (an empty organ)");
  std::vector<int> all;
  for (const auto& o : organs) all.insert(all.end(), o.values.begin(), o.values.end());
  for (const std::string& role : case_roles()) {
    const auto it = std::find_if(organs.begin(), organs.end(), [&](const OrganLabels& o) { return o.role == role; });
    if (it == organs.end()) continue;
    CaseOrgan co;
    co.role = role;
    co.values = it->values;
    SurfaceOptions opt;
    opt.edge_mm = edge_mm(role);
    // The fat component is the block the organs sit in (the scenario excludes the organs from
    // it): the fat voxels and every organ's together.
    const std::vector<int>& mask = role == "fat" ? all : it->values;
    co.surface = label_surface(volume, mask, opt, role + " (label " + values_text(it->values) + ")", &co.stats);
    c.organs.push_back(std::move(co));
  }
  if (!find(c, "fat")) {
    Vec3 lo, hi, l2, h2;
    bounds(c.organs.front().surface, lo, hi);
    for (const auto& o : c.organs) {
      bounds(o.surface, l2, h2);
      lo = lo.cwiseMin(l2);
      hi = hi.cwiseMax(h2);
    }
    const Vec3 margin = Vec3::Constant(kFatMarginMm * 1e-3);
    CaseOrgan fat;
    fat.role = "fat";
    fat.surface = anatomy::grid_box(lo - margin, hi + margin, edge_mm("fat") * 1e-3);
    c.organs.push_back(std::move(fat));
  }

  // The probe: on the rectum's centre line (mean of its surface points within 3 mm of the
  // prostate centre's height), kProbeBelowMm below that centre, pointing superior.
  Vec3 plo, phi;
  bounds(find(c, "prostate")->surface, plo, phi);
  const Vec3 centre = 0.5 * (plo + phi);
  const TriMesh& rectum = find(c, "rectum")->surface;
  Vec3 sum = Vec3::Zero();
  int count = 0;
  for (const Vec3& v : rectum.vertices)
    if (std::abs(v.z() - centre.z()) < 3e-3) {
      sum += v;
      ++count;
    }
  Vec3 rlo, rhi;
  bounds(rectum, rlo, rhi);
  const Vec3 axis = count > 0 ? Vec3(sum / count) : Vec3(0.5 * (rlo + rhi));
  const double z = std::max(centre.z() - kProbeBelowMm * 1e-3, rlo.z() + 5e-3);
  c.probe_entry_m = Vec3(axis.x(), axis.y(), z);
  c.probe_entry_in_rectum = MeshQuery(rectum).inside(c.probe_entry_m);
  return c;
}

std::string case_scenario_yaml(const PatientCase& c) {
  const bool bladder = find(c, "bladder") != nullptr, bone = find(c, "bone") != nullptr;
  const CaseOrgan* fat = find(c, "fat");
  std::string s;
  s += "# A patient's case from the label map " + c.source + " (`prostatesim make-anatomy --from-labels`):\n";
  s += "# the organ surfaces beside this file, in the label map's patient RAS frame (mm), with the\n";
  s += "# materials, probe and biopsy needle of config/biopsy.yaml (sources there and in docs/anatomy.md).\n";
  s += "# No lesion: add a `tags:` region and an override as config/biopsy.yaml does.\n";
  s += "name: case\n";
  s += "solver: {pressure_iterations: 1, mass_scaling: true, multirate: true, multirate_inertia: 4}\n";
  s += "time: {dt_ms: 2, substeps: 3, duration_s: 1}\n";
  s += "gravity_m_s2: [-9.81, 0, 0]   # left lateral decubitus\n";
  s += "rest: {kinetic_energy_j: 1.0e-7, hold_s: 0.05}\n\n";
  s += "materials:\n";
  s += "  prostate: {model: tet, young_kpa: 40, density_kg_m3: 1050, damping_1_s: 40, incompressible: true, pressure: implicit, k_c_n: 1.5, k_f_n: 0.05}\n";
  if (bladder) s += "  bladder_wall: {model: shell, thickness_mm: 4, young_kpa: 20, density_kg_m3: 1040, damping_1_s: 40, incompressible: true, k_c_n: 1.0, k_f_n: 0.03}\n";
  s += "  rectal_wall: {model: shell, thickness_mm: 3, young_kpa: 20, density_kg_m3: 1040, damping_1_s: 40, k_c_n: 1.0, k_f_n: 0.03}\n";
  s += "  fat: {model: tet, young_kpa: 3, density_kg_m3: 940, damping_1_s: 40, k_c_n: 0.3, k_f_n: 0.02}\n";
  if (bone) s += "  bone: {young_kpa: 1.0e7, density_kg_m3: 1900}\n";
  s += "\ncomponents:\n";
  s += "  - name: prostate\n    role: prostate\n    material: prostate\n    spacing_mm: 6\n    mesh: {file: prostate.obj, units: mm}\n";
  if (bladder) s += "  - name: bladder\n    role: bladder\n    material: bladder_wall\n    spacing_mm: 8\n    fill: surface\n    mesh: {file: bladder.obj, units: mm}\n";
  s += "  - name: rectum\n    role: rectum\n    material: rectal_wall\n    spacing_mm: 7\n    fill: surface\n    mesh: {file: rectum.obj, units: mm}\n";
  if (bone) s += "  - name: bone\n    role: bone\n    type: rigid\n    kinematic: true\n    material: bone\n    spacing_mm: 7\n    fill: surface\n    mesh: {file: bone.obj, units: mm}\n";
  std::string organs = "prostate";
  if (bladder) organs += ", bladder";
  organs += ", rectum";
  if (bone) organs += ", bone";
  s += "  - name: fat\n    role: fat\n    material: fat\n    spacing_mm: 10\n    mesh: {file: fat.obj, units: mm}\n";
  s += "    exclude_inside: [" + organs + "]\n\n";
  s += "links:\n";
  s += "  - {a: fat, b: prostate, distance_mm: 14}\n";
  if (bladder) s += "  - {a: fat, b: bladder, distance_mm: 14}\n";
  s += "  - {a: fat, b: rectum, distance_mm: 14}\n";
  if (bone) s += "  - {a: fat, b: bone, distance_mm: 10}\n";
  if (bladder) s += "  - {a: prostate, b: bladder, distance_mm: 8}\n";
  s += "  - {a: prostate, b: rectum, distance_mm: 8}\n\n";
  // the fat's outer walls held, 1 mm deep, as in config/biopsy.yaml; its inferior side (the
  // perineum) free
  Vec3 lo, hi;
  bounds(fat->surface, lo, hi);
  const Vec3 in = Vec3::Constant(1e-3);
  lo += in;
  hi -= in;
  const Vec3 mid = 0.5 * (lo + hi);
  s += "constraints:\n";
  s += "  # the fat's outer walls stand for the pelvic side walls, sacrum, abdomen and pubis; its inferior side stays free\n";
  s += "  - fix: {component: fat, region: {half_space: {point_mm: " + mm3(Vec3(hi.x(), mid.y(), mid.z())) + ", normal: [1, 0, 0]}}}\n";
  s += "  - fix: {component: fat, region: {half_space: {point_mm: " + mm3(Vec3(lo.x(), mid.y(), mid.z())) + ", normal: [-1, 0, 0]}}}\n";
  s += "  - fix: {component: fat, region: {half_space: {point_mm: " + mm3(Vec3(mid.x(), lo.y(), mid.z())) + ", normal: [0, -1, 0]}}}\n";
  s += "  - fix: {component: fat, region: {half_space: {point_mm: " + mm3(Vec3(mid.x(), hi.y(), mid.z())) + ", normal: [0, 1, 0]}}}\n";
  s += "  - fix: {component: fat, region: {half_space: {point_mm: " + mm3(Vec3(mid.x(), mid.y(), hi.z())) + ", normal: [0, 0, 1]}}}\n\n";
  s += "prostate_zones: {component: prostate, peripheral_depth_mm: 8}\n\n";
  const Vec3 e = c.probe_entry_m;
  s += "# TRUS probe in the rectal lumen: entry on the rectum's centre line " + mm(kProbeBelowMm * 1e-3) + " mm below the prostate centre\n";
  if (!c.probe_entry_in_rectum) s += "# CHECK: this entry is not inside the rectum surface; move entry_mm into the lumen\n";
  s += "probe:\n  radius_mm: 10\n  length_mm: 45\n";
  s += "  entry_mm: " + mm3(e) + "\n  axis: [0, 0, 1]\n  anterior: [0, 1, 0]\n  pose: {insertion_mm: 40}\n";
  s += "  needle_guide: {angle_deg: 25, back_mm: 32}\n\n";
  // the needle in the guide at the biopsy script's probe insertion of 45 mm, as config/biopsy.yaml
  const Vec3 start = e + Vec3(0, 10e-3, 13e-3);
  s += "needles:\n  puncture_n: {prostate: 2.0, rectum: 1.5}\n  instruments:\n";
  s += "    - name: biopsy_1\n      preset: biopsy_18g\n      start_mm: " + mm3(start) + "\n";
  s += "      direction: [0, 0.4226, 0.9063]\n      gun: {}\n";
  return s;
}

void write_patient_case(const std::string& folder, const PatientCase& c) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& o : c.organs) {
    std::vector<std::string> header = {
        "ProstateSim patient case: " + o.role + " from " + c.source +
            (o.values.empty() ? std::string(" (no fat label: a block around the organs)") : " label " + values_text(o.values)),
        "frame: the label map's patient RAS, mm",
        "closed outward 2-manifold surface; " + std::to_string(o.surface.vertices.size()) + " vertices, " +
            std::to_string(o.surface.faces.size()) + " faces"};
    files.emplace_back(o.role + ".obj", anatomy::to_mm_obj(o.surface, header));
  }
  files.emplace_back("scenario.yaml", case_scenario_yaml(c));
  for (const auto& [name, text] : files) write_file_atomic((std::filesystem::path(folder) / name).string(), text);
}

}  // namespace ps::labelmap
