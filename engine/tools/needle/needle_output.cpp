#include "engine/tools/needle/needle_output.h"

#include <cstdio>

#include "engine/tools/needle/biopsy.h"
#include "engine/util/atomic_file.h"

namespace ps {

namespace {
std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}
std::string g(double v) { return fmt("%.9g", v); }
std::string mm(double v) { return fmt("%.6f", v * 1e3); }
// RFC 4180 quoting when a text field holds a comma, quote or line break (zone labels do not today)
std::string csv_field(const std::string& v) {
  if (v.find_first_of(",\"\n\r") == std::string::npos) return v;
  std::string q = "\"";
  for (char ch : v) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}
}  // namespace

void ForceDepthRecorder::sample(const NeedleTool& tool, double time) {
  for (int i = 0; i < tool.count() && i < static_cast<int>(samples_.size()); ++i) {
    const NeedleReadout& r = tool.readout(i);
    ForceDepthSample s;
    s.time = time;
    s.depth = r.depth;
    s.plan_depth = r.plan_depth;
    s.axial_force = r.axial_force_tick;
    s.press_force = r.press_force;
    s.cutting_force = r.cutting_force;
    s.friction_force = r.friction_force;
    s.tip = r.tip;
    s.engaged_nodes = r.engaged_nodes;
    s.stuck_nodes = r.stuck_nodes;
    s.contacted = r.contacted;
    samples_[i].push_back(s);
  }
}

ForceDepthMetrics force_depth_metrics(const std::vector<ForceDepthSample>& samples, double plateau_lo, double plateau_hi) {
  ForceDepthMetrics r;
  double sum = 0.0;
  bool any = false;
  for (const auto& s : samples) {
    if (!s.contacted) continue;
    if (!any || s.axial_force > r.peak_force) {
      r.peak_force = s.axial_force;
      r.peak_depth = s.depth;
    }
    any = true;
    r.end_force = s.axial_force;
    r.end_depth = s.depth;
  }
  for (const auto& s : samples)
    if (s.contacted && s.depth > r.peak_depth && s.depth >= plateau_lo && s.depth <= plateau_hi) {
      sum += s.axial_force;
      ++r.plateau_samples;
    }
  if (r.plateau_samples > 0) r.plateau_force = sum / r.plateau_samples;
  return r;
}

std::string force_depth_csv(const std::vector<ForceDepthSample>& samples) {
  std::string out =
      "time_s,depth_mm,plan_depth_mm,axial_force_n,press_n,cutting_n,friction_n,tip_x_mm,tip_y_mm,tip_z_mm,engaged_nodes,"
      "stuck_nodes,contacted\n";
  for (const auto& s : samples)
    out += g(s.time) + "," + mm(s.depth) + "," + mm(s.plan_depth) + "," + g(s.axial_force) + "," + g(s.press_force) + "," +
           g(s.cutting_force) + "," + g(s.friction_force) + "," + mm(s.tip.x()) + "," + mm(s.tip.y()) + "," + mm(s.tip.z()) + "," +
           std::to_string(s.engaged_nodes) + "," + std::to_string(s.stuck_nodes) + "," + (s.contacted ? "1" : "0") + "\n";
  return out;
}

void write_force_depth_csv(const std::string& path, const std::vector<ForceDepthSample>& samples) {
  write_file_atomic(path, force_depth_csv(samples));
}

std::string needle_events_csv(const NeedleTool& tool, const Model& model) {
  std::string out = "time_s,needle,event,component,node,depth_mm,force_n,x_mm,y_mm,z_mm,value\n";
  for (const NeedleEvent& e : tool.events().snapshot()) {
    const std::string comp = e.component >= 0 ? model.components[e.component].name : "";
    out += g(e.time) + "," + tool.spec(e.needle).name + "," + needle_event_name(e.kind) + "," + comp + "," +
           std::to_string(e.node) + "," + mm(e.depth) + "," + g(e.force) + "," + mm(e.position.x()) + "," + mm(e.position.y()) +
           "," + mm(e.position.z()) + "," + g(e.value) + "\n";
  }
  return out;
}

std::string seeds_csv(const NeedleTool& tool) {
  std::string out =
      "needle,seed,deposited,embedded,time_s,planned_x_mm,planned_y_mm,planned_z_mm,deposited_x_mm,deposited_y_mm,"
      "deposited_z_mm,current_x_mm,current_y_mm,current_z_mm,error_mm\n";
  for (const SeedReport& s : tool.seeds())
    out += tool.spec(s.needle).name + "," + std::to_string(s.index) + "," + (s.deposited ? "1" : "0") + "," +
           (s.embedded ? "1" : "0") + "," + g(s.time) + "," + mm(s.planned.x()) + "," + mm(s.planned.y()) + "," +
           mm(s.planned.z()) + "," + mm(s.deposited_at.x()) + "," + mm(s.deposited_at.y()) + "," + mm(s.deposited_at.z()) +
           "," + mm(s.current.x()) + "," + mm(s.current.y()) + "," + mm(s.current.z()) + "," + mm(s.error) + "\n";
  return out;
}

std::string cores_csv(const NeedleTool& tool) {
  std::string out = "needle,taken,time_s,component,particles,tumour_particles,tumour_length_mm,notch_length_mm,site\n";
  // one row per component and per tag ("tag:NAME") found in the notch; every row of a core
  // repeats the core's values and its clinical site (the 12-core zone name, biopsy.h)
  for (int i = 0; i < tool.count(); ++i) {
    if (!tool.spec(i).gun) continue;
    std::vector<CoreReport> list = tool.cores(i);  // every core (a needle in the guide takes several)
    if (list.empty()) list.push_back(tool.core(i));
    for (const CoreReport& c : list) {
      const std::string head = tool.spec(i).name + "," + (c.taken ? "1" : "0") + "," + g(c.time) + ",";
      const std::string tail = "," + std::to_string(c.tumour_particles) + "," + mm(c.tumour_length) + "," + mm(c.notch_length) +
                               "," + csv_field(core_site(c).label) + "\n";
      if (c.per_component.empty()) out += head + ",0" + tail;
      for (const auto& [name, count] : c.per_component) out += head + name + "," + std::to_string(count) + tail;
      for (const auto& [name, count] : c.per_tag) out += head + "tag:" + name + "," + std::to_string(count) + tail;
    }
  }
  return out;
}

}  // namespace ps
