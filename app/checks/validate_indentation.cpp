#include "app/checks/validate_indentation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "engine/scenario/compile.h"
#include "engine/scenario/material_models.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/run.h"
#include "engine/step/stages.h"

namespace ps::app {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTop = 0.060;             // block top z [m]
constexpr double kPunchA = 0.010, kPunchD = 0.002;  // punch radius, depth [m] (punch_halfspace.yaml)
constexpr double kSphereR = 0.040;         // [m]
constexpr double kDepth1 = 0.0015, kDepth2 = 0.003;  // sphere depths [m]
constexpr double kYoung = 10e3, kPoisson = 0.49;     // of the FEM (and the scenarios' E) [Pa], [-]

std::string g_model;
std::vector<double> g_spacings = {10.0, 5.0};  // [mm]

// Rigid frictionless sphere: particles above its lower surface are put back on it vertically.
// depth(t) rises by smoothstep from `from` to `to` over [t0, t0 + ramp].
class SphereIndenter : public Tool {
 public:
  const char* name() const override { return "sphere_indenter"; }
  void move_to(double depth, double t0) { from_ = depth_at(t0); to_ = depth; t0_ = t0; }
  double depth_at(double t) const {
    const double u = std::clamp((t - t0_) / kRamp, 0.0, 1.0);
    return from_ + (to_ - from_) * u * u * (3.0 - 2.0 * u);
  }
  void constraints(const Model& m, State& s, double) override {
    const double cz = kTop - depth_at(s.time) + kSphereR;  // s.time: start of the step; fine at rest
    for (int p = 0; p < m.particle_count(); ++p) {
      if (m.inv_mass[p] == 0.0 || (m.locked_axes[p] & 4)) continue;
      const double r2 = s.x[p].x() * s.x[p].x() + s.x[p].y() * s.x[p].y();
      if (r2 >= kSphereR * kSphereR) continue;
      const double zs = cz - std::sqrt(kSphereR * kSphereR - r2);
      if (s.x[p].z() > zs) { s.x[p].z() = zs; s.contact[p] |= 4; }
    }
  }

 private:
  static constexpr double kRamp = 0.3;  // [s]
  double from_ = 0.0, to_ = 0.0, t0_ = 0.0;
};

void settle(Simulation& sim, const ScenarioSpec& spec, long long& steps) {
  RunOptions opt;
  opt.duration = spec.duration;
  opt.until_rest = true;
  opt.rest_energy = spec.rest_kinetic_energy;
  opt.rest_hold = spec.rest_hold;
  const RunResult r = run_simulation(sim, opt);
  steps += r.steps;
  if (r.faulted) throw std::runtime_error(spec.name + ": simulation fault: " + r.fault);
  if (!r.at_rest) throw std::runtime_error(spec.name + ": did not come to rest within " + std::to_string(spec.duration) + " s");
}

// Elastic force on every particle at the current state (no external, no constraint force) [N]
std::vector<Vec3> elastic_forces(const Model& m, const State& s0) {
  State s = s0;
  for (auto& f : s.f) f.setZero();
  if (m.any_shape_memory) add_shape_memory_forces(m, s);
  if (m.strain.count() > 0) add_strain_memory_forces(m, s, 50);
  if (m.tets.count() > 0) add_tet_elastic_forces(m, s);
  return s.f;
}

struct FemField {
  std::map<std::array<long, 3>, Vec3> u;  // key: position in 0.1 mm units -> displacement [m]
  double umax = 0.0;                       // [m]
  std::vector<std::pair<double, double>> force;  // (depth, force) from the header [m], [N]
};

std::array<long, 3> key_of(const Vec3& p) {
  return {std::lround(p.x() * 1e4), std::lround(p.y() * 1e4), std::lround(p.z() * 1e4)};
}

FemField load_fem(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read the FEM reference " + path);
  FemField f;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream ls(line);
    if (line[0] == '#') {
      std::string hash, kase, w;
      double depth = 0, force = 0;
      ls >> hash >> kase >> w;
      if (w == "depth_mm" && (ls >> depth >> w >> force)) f.force.emplace_back(depth * 1e-3, force);
      continue;
    }
    double v[6];
    for (double& a : v) ls >> a;
    if (!ls) throw std::runtime_error(path + ": malformed line '" + line + "'");
    const Vec3 u(v[3] * 1e-3, v[4] * 1e-3, v[5] * 1e-3);
    f.u[key_of(Vec3(v[0], v[1], v[2]) * 1e-3)] = u;
    f.umax = std::max(f.umax, u.norm());
  }
  return f;
}

// RMS and max of |u - u_fem| over the free particles, relative to the FEM's largest displacement.
// The FEM solved the quarter x, y >= 0 (symmetry planes x = 0, y = 0); the simulation runs the
// whole block (a particle model's neighbourhoods are not symmetric about a cut plane: measured,
// the quarter model hides most of the strain model's error), so a particle at (x, y) reads the
// FEM at (|x|, |y|) with ux, uy mirrored.
void field_error(const Model& m, const State& s, const FemField& fem, IndentationAnswer& a) {
  double sum = 0.0, mx = 0.0;
  int count = 0;
  for (int p = 0; p < m.particle_count(); ++p) {
    if (m.locked_axes[p] & 4) continue;  // base and punch: prescribed
    const Vec3 rp = m.rest_pos[p];
    const auto it = fem.u.find(key_of(Vec3(std::abs(rp.x()), std::abs(rp.y()), rp.z())));
    if (it == fem.u.end()) throw std::runtime_error("particle at a point the FEM field does not have (spacing must be a multiple of 5 mm)");
    Vec3 uf = it->second;
    if (rp.x() < 0) uf.x() = -uf.x();
    if (rp.y() < 0) uf.y() = -uf.y();
    const double e = (s.x[p] - m.rest_pos[p] - uf).norm();
    sum += e * e;
    mx = std::max(mx, e);
    ++count;
  }
  a.field_rms = std::sqrt(sum / count) / fem.umax;
  a.field_max = mx / fem.umax;
}

double boussinesq(double r) { return -(2.0 * kPunchD / kPi) * std::asin(kPunchA / r); }

}  // namespace

void set_indentation_model(const std::string& model) { g_model = model; }
void set_indentation_spacings(const std::vector<double>& spacings_mm) {
  g_spacings = spacings_mm.empty() ? std::vector<double>{10.0, 5.0} : spacings_mm;
}

IndentationAnswer run_indentation(const std::string& src, const std::string& name, double spacing_mm, const std::string& model) {
  ScenarioSpec spec = parse_scenario_file(src + "/config/validation/" + name + ".yaml");
  for (auto& c : spec.components) c.spacing = spacing_mm * 1e-3;
  for (auto& mat : spec.materials) {
    if (model.empty()) continue;
    if (model != "paper" && model != "strain" && model != "tet") throw std::invalid_argument("unknown model '" + model + "'");
    mat.model = find_material_model(model)->model;
  }
  const std::string field = name == "punch_halfspace" ? "punch_fem_field.txt" : "sphere_fem_field.txt";
  const FemField fem = load_fem(src + "/docs/reference/" + field);
  Simulation sim(compile_scenario(spec));
  const Model& m = sim.model();
  IndentationAnswer a;
  a.spacing_mm = spacing_mm;
  a.particles = m.particle_count();
  a.stable_dt = m.stable_dt_estimate;
  a.substep_s = m.dt / m.substeps;
  if (name == "punch_halfspace") {
    settle(sim, spec, a.substeps);
    field_error(m, sim.state(), fem, a);
    // top-surface profile outside the punch against Boussinesq, for the simulation and the FEM
    double se = 0.0, sf = 0.0;
    int ne = 0, nf = 0;
    for (int p = 0; p < m.particle_count(); ++p) {
      const Vec3 r = m.rest_pos[p];
      const double rho = std::hypot(r.x(), r.y());
      if (r.z() < kTop - 1e-6 || rho <= kPunchA + 1e-6) continue;
      const double e = (sim.state().x[p].z() - r.z()) - boussinesq(rho);
      se += e * e;
      ++ne;
    }
    for (const auto& [k, u] : fem.u) {
      const double rho = std::hypot(k[0], k[1]) * 1e-4;
      if (k[2] != std::lround(kTop * 1e4) || rho <= kPunchA + 1e-6) continue;
      const double e = u.z() - boussinesq(rho);
      sf += e * e;
      ++nf;
    }
    a.profile_rms = std::sqrt(se / ne) / kPunchD;
    a.fem_profile_rms = std::sqrt(sf / nf) / kPunchD;
  } else {
    auto tool = std::make_unique<SphereIndenter>();
    SphereIndenter* ind = tool.get();
    sim.add_tool(std::move(tool));
    auto force_now = [&] {
      const std::vector<Vec3> f = elastic_forces(m, sim.state());
      double fz = 0.0;
      for (int p = 0; p < m.particle_count(); ++p)
        if (sim.state().contact[p] & 4) fz += f[p].z();
      return fz;
    };
    ind->move_to(kDepth1, 0.0);
    settle(sim, spec, a.substeps);
    a.force1 = force_now();
    ind->move_to(kDepth2, sim.state().time);
    settle(sim, spec, a.substeps);
    a.force2 = force_now();
    field_error(m, sim.state(), fem, a);
  }
  return a;
}

std::vector<ValidationCase> indentation_validation_cases() {
  std::vector<ValidationCase> cases;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // Field tolerances (issue 9): RMS <= 5 % of the largest displacement at the scene spacing
  // (10 mm, the default anatomy's range is 6-10 mm) and smaller at 5 mm; the max is reported.
  constexpr double kRmsTol = 0.05;
  auto tag = [](double h) {
    char b[32];
    std::snprintf(b, sizeof b, "@%gmm", h);
    return std::string(b);
  };
  cases.push_back({"punch_halfspace", "flat punch on a block vs Boussinesq profile and a CalculiX field, at 10 and 5 mm",
                   [=](const std::string& src, const std::string&) {
                     std::vector<ValidationRow> rows;
                     std::vector<IndentationAnswer> at(g_spacings.size());
                     for (size_t i = 0; i < g_spacings.size(); ++i) {
                       at[i] = run_indentation(src, "punch_halfspace", g_spacings[i], g_model);
                       const std::string h = tag(g_spacings[i]);
                       rows.push_back({"punch_halfspace", "field_rms_rel" + h, at[i].field_rms, 0.0, "-", kRmsTol});
                       rows.push_back({"punch_halfspace", "field_max_rel" + h, at[i].field_max, kNaN, "-", kNaN});
                       // the finite block departs from the half-space: compare with the FEM's own departure
                       rows.push_back({"punch_halfspace", "boussinesq_profile_rms_rel" + h, at[i].profile_rms,
                                       at[i].fem_profile_rms, "-", kRmsTol});
                     }
                     // finer must be more accurate: the change of the RMS error from the first spacing to the last is negative
                     if (at.size() > 1)
                       rows.push_back({"punch_halfspace", "field_rms_rel.change", at.back().field_rms - at[0].field_rms, -1.0, "-", 1.0});
                     return rows;
                   }});
  cases.push_back({"sphere_indentation", "rigid sphere on a block vs Hertz force-depth and a CalculiX field, at 10 and 5 mm",
                   [=](const std::string& src, const std::string&) {
                     std::vector<ValidationRow> rows;
                     const FemField fem = load_fem(src + "/docs/reference/sphere_fem_field.txt");
                     const double es = kYoung / (1.0 - kPoisson * kPoisson);
                     auto hertz = [&](double d) { return 4.0 / 3.0 * es * std::sqrt(kSphereR) * std::pow(d, 1.5); };
                     std::vector<IndentationAnswer> at(g_spacings.size());
                     for (size_t i = 0; i < g_spacings.size(); ++i) {
                       at[i] = run_indentation(src, "sphere_indentation", g_spacings[i], g_model);
                       const std::string h = tag(g_spacings[i]);
                       rows.push_back({"sphere_indentation", "field_rms_rel" + h, at[i].field_rms, 0.0, "-", kRmsTol});
                       rows.push_back({"sphere_indentation", "field_max_rel" + h, at[i].field_max, kNaN, "-", kNaN});
                       // force against the FEM of the same block (10 %), and Hertz's half-space law:
                       // exponent 1.5 between the two depths, magnitude reported. A force is only
                       // held to a tolerance where the Hertz contact radius sqrt(R d) spans at least
                       // one spacing (at 10 mm the 1.5 mm contact, 7.7 mm across, is one particle):
                       // otherwise the row is reported without a reference.
                       const double h_m = g_spacings[i] * 1e-3;
                       auto resolved = [&](double d) { return std::sqrt(kSphereR * d) >= h_m; };
                       for (const auto& [d, f] : fem.force) {
                         const double sim_f = d < 0.5 * (kDepth1 + kDepth2) ? at[i].force1 : at[i].force2;
                         const std::string dm = "@d" + std::to_string(d * 1e3).substr(0, 3) + "mm";
                         rows.push_back({"sphere_indentation", "force_N" + dm + h, sim_f, resolved(d) ? f : kNaN, "N",
                                         resolved(d) ? 0.1 * f : kNaN});
                         rows.push_back({"sphere_indentation", "force_over_hertz" + dm + h, sim_f / hertz(d), kNaN, "-", kNaN});
                       }
                       const bool both = resolved(kDepth1) && resolved(kDepth2);
                       rows.push_back({"sphere_indentation", "force_exponent" + h,
                                       std::log(at[i].force2 / at[i].force1) / std::log(kDepth2 / kDepth1), both ? 1.5 : kNaN,
                                       "-", both ? 0.15 : kNaN});
                     }
                     if (at.size() > 1)
                       rows.push_back({"sphere_indentation", "field_rms_rel.change", at.back().field_rms - at[0].field_rms, -1.0, "-", 1.0});
                     return rows;
                   }});
  return cases;
}

}  // namespace ps::app
