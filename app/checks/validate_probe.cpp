// Probe and filling displacement studies (issue 5) and their validation rows.
#include "app/checks/validate_probe.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "engine/util/error.h"
#include "engine/util/sim_fault.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/step/stages.h"
#include "engine/tools/filling/filling.h"
#include "engine/tools/probe/probe.h"

namespace ps::app {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kPush = 0.006;       // probe offset toward the prostate: 4 mm past the 2 mm gap [m]
constexpr double kTilt = 7.0 * kDeg;  // biopsy-like tilt about the anal entry [rad]

struct Loads {
  bool filling = false;      // bladder x2 over [0.02, 0.12] s (the scene's schedule)
  bool imposed = false;      // paper's imposed mode
  double push = 0.0;         // [m]
  double tilt = 0.0;         // [rad]
  int settle_before = 0;     // ticks before the probe moves (reference taken then)
  int ticks = 0;             // ticks after the reference
};

Loads loads_of(const std::string& name) {
  if (name == "bladder_doubling") return {true, false, 0.0, 0.0, 0, 180};
  if (name == "probe_push") return {false, false, kPush, 0.0, 0, 120};
  if (name == "probe_tilt") return {false, false, 0.0, kTilt, 0, 120};
  if (name == "probe_imposed") return {false, true, kPush, 0.0, 0, 120};
  if (name == "probe_full_bladder") return {true, false, kPush, 0.0, 180, 120};
  throw std::invalid_argument("unknown displacement study '" + name + "'");
}

}  // namespace

DisplacementStudy run_displacement_study(const std::string& source_dir, const std::string& name) {
  const Loads L = loads_of(name);
  ScenarioSpec spec = parse_scenario_file(source_dir + "/config/validation/probe_pelvis_box.yaml");
  spec.probe->imposed_mode = L.imposed;
  DisplacementStudy st;
  st.name = name;
  st.model = compile_scenario(spec);
  const Model& m = *st.model;
  Simulation sim(st.model);
  auto probe_tool = make_probe_tool(spec, m);
  ProbeTool* probe = probe_tool.get();
  sim.add_tool(std::move(probe_tool));
  FillingTool* filling = nullptr;
  if (L.filling) {
    auto f = make_filling_tool(spec, m);
    filling = f.get();
    sim.add_tool(std::move(f));
  }
  const int pc = m.find_role(Role::Prostate), bc = m.find_role(Role::Bladder);
  const Surface& ps_ = m.surfaces[m.components[pc].surface];
  const Surface& bs = m.surfaces[m.components[bc].surface];
  auto tick = [&] {
    if (!sim.tick()) throw SimulationFault(name + ": simulation fault: " + sim.state().fault.describe(m));
    const State& s = sim.state();
    st.worst_volume_error = std::max(st.worst_volume_error, std::abs(surface_volume(ps_, s.x) / s.target_volume[m.components[pc].surface] - 1.0));
    st.worst_volume_error = std::max(st.worst_volume_error, std::abs(surface_volume(bs, s.x) / s.target_volume[m.components[bc].surface] - 1.0));
    for (int p = 0; p < m.particle_count(); ++p)
      if (m.inv_mass[p] > 0.0 && m.locked_axes[p] == 0)
        st.worst_penetration = std::max(st.worst_penetration, -capsule_signed_distance(probe->frame().capsule, s.x[p]));
  };
  for (int i = 0; i < L.settle_before; ++i) tick();
  st.ref = sim.state().x;
  if (L.push != 0.0 || L.tilt != 0.0) {
    ProbePose target = probe->pose();
    target.offset = Vec3(0, L.push, 0);
    target.tilt = L.tilt;
    probe->move_to(target, 0.0);  // at the scene's speed limits
  }
  for (int i = 0; i < L.ticks; ++i) tick();
  st.x = sim.state().x;
  st.prostate = displacement_stats(m, pc, st.ref, st.x, Vec3::UnitZ());
  st.probe_force = probe->reaction_force();
  st.reports = probe->reports();
  if (filling) {
    const std::vector<std::string> f = filling->reports();  // formatted from the ring, by value
    st.reports.insert(st.reports.end(), f.begin(), f.end());
  }
  return st;
}

namespace {
std::string& output_dir() {
  static std::string dir = "out/validate";
  return dir;
}
}  // namespace

void set_displacement_output_dir(const std::string& dir) { output_dir() = dir; }
const std::string& displacement_output_dir() { return output_dir(); }

void write_study_csv(const DisplacementStudy& study, const std::string& path) {
  write_displacement_csv(path, *study.model, -1, study.ref, study.x, Vec3::UnitZ());
}

std::vector<ValidationCase> probe_validation_cases() {
  std::vector<ValidationCase> cases;
  auto add = [&](const std::string& name, const std::string& description, bool probe_moves) {
    cases.push_back({name, description, [name, probe_moves](const std::string& root, const std::string&) {
                       const DisplacementStudy s = run_displacement_study(root, name);
                       std::filesystem::create_directories(displacement_output_dir());
                       const std::string csv = displacement_output_dir() + "/" + name + "_displacement.csv";
                       write_study_csv(s, csv);
                       std::printf("%-18s per-particle displacement: %s\n", name.c_str(), csv.c_str());
                       const DisplacementStats& d = s.prostate;
                       std::vector<ValidationRow> rows;
                       auto mm = [&](const std::string& metric, double v) { rows.push_back({name, metric, v * 1e3, kNaN, "mm", 0.0}); };
                       rows.push_back({name, "volume error bladder+prostate (max)", s.worst_volume_error, 0.0, "", 1e-9});
                       mm("prostate displacement mean", d.all.mean);
                       mm("prostate displacement max", d.all.max);
                       mm("prostate base mean", d.base.mean);
                       mm("prostate mid mean", d.mid.mean);
                       mm("prostate apex mean", d.apex.mean);
                       if (probe_moves) {
                         mm("prostate mean anterior (+y)", d.all.mean_vec.y());
                         mm("prostate base anterior (+y)", d.base.mean_vec.y());
                         mm("prostate apex anterior (+y)", d.apex.mean_vec.y());
                         rows.push_back({name, "probe penetration (max, any tick)", s.worst_penetration * 1e3, 0.0, "mm", 0.1});
                         rows.push_back({name, "probe reaction force |F|", s.probe_force.norm(), kNaN, "N", 0.0});
                       } else {
                         mm("prostate base inferior (-z)", -d.base.mean_vec.z());
                         mm("prostate base posterior (-y)", -d.base.mean_vec.y());
                         mm("prostate apex inferior (-z)", -d.apex.mean_vec.z());
                       }
                       return rows;
                     },
                     /*writes_files=*/true});
  };
  add("bladder_doubling", "bladder volume x2 (paper Fig. 11-12): prostate displacement, volumes exact", false);
  add("probe_push", "probe pushed 6 mm toward the prostate (4 mm into the rectal wall), contact mode", true);
  add("probe_tilt", "probe tilted 7 deg about the anal entry (biopsy): base moves more than apex", true);
  add("probe_imposed", "probe push of probe_push in the paper's imposed-displacement mode", true);
  add("probe_full_bladder", "probe push of probe_push after the bladder has doubled (paper §5.4.1)", true);
  return cases;
}

}  // namespace ps::app
