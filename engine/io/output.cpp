#include "engine/io/output.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "engine/util/atomic_file.h"

namespace ps {

std::string particles_csv(const Model& m, const State& s) {
  std::string out = "id,component,x0_mm,y0_mm,z0_mm,x_mm,y_mm,z_mm\n";
  char line[256];
  for (int p = 0; p < m.particle_count(); ++p) {
    const Vec3 a = m.rest_pos[p] * 1e3, b = s.x[p] * 1e3;
    std::snprintf(line, sizeof line, "%d,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", p,
                  m.components[m.component_of[p]].name.c_str(), a[0], a[1], a[2], b[0], b[1], b[2]);
    out += line;
  }
  return out;
}

void write_particles_csv(const std::string& path, const Model& m, const State& s) {
  write_file_atomic(path, particles_csv(m, s));
}

void write_summary_json(const std::string& path, const Model& m, const RunResult& r) {
  nlohmann::json j;
  j["scenario"] = m.name;
  j["steps"] = r.steps;
  j["sim_time_s"] = r.sim_time;
  j["wall_time_s"] = r.wall_time;
  j["kinetic_energy_J"] = r.kinetic_energy;
  j["max_speed_m_s"] = r.max_speed;
  j["volume_error"] = nlohmann::json::object();
  for (const auto& [k, v] : r.volume_error) j["volume_error"][k] = v;
  j["warnings"] = r.warnings;
  j["particles"] = m.particle_count();
  j["substeps"] = m.substeps;
  j["dt_s"] = m.dt;
  j["stable_substep_estimate_s"] = m.stable_dt_estimate;
  if (r.faulted) j["fault"] = r.fault;
  write_file_atomic(path, j.dump(2) + "\n");
}

TriMesh component_surface_mesh(const Model& m, const State& s, int component) {
  TriMesh mesh;
  const int si = m.components[component].surface;
  if (si < 0) return mesh;
  const Surface& surf = m.surfaces[si];
  std::unordered_map<int, int> local;
  for (int p : surf.vertices) {
    local[p] = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(s.x[p]);
  }
  for (const auto& f : surf.faces) mesh.faces.push_back({local[f[0]], local[f[1]], local[f[2]]});
  return mesh;
}

void write_surface_obj(const std::string& path, const TriMesh& mesh) {
  std::string out = "# ProstateSim surface, millimetres\n";
  char line[160];
  for (const Vec3& v : mesh.vertices) {
    std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", v[0] * 1e3, v[1] * 1e3, v[2] * 1e3);
    out += line;
  }
  for (const auto& f : mesh.faces) {
    std::snprintf(line, sizeof line, "f %d %d %d\n", f[0] + 1, f[1] + 1, f[2] + 1);
    out += line;
  }
  write_file_atomic(path, out);
}

}  // namespace ps
