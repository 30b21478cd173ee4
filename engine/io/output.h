// Files written by `simulate`: particles.csv, summary.json, one OBJ per component surface.
// Every file is written atomically (temp + rename).
#pragma once
#include <string>

#include "engine/mesh/tri_mesh.h"
#include "engine/model/model.h"
#include "engine/sim/run.h"
#include "engine/state/state.h"

namespace ps {

// header: id,component,x0_mm,y0_mm,z0_mm,x_mm,y_mm,z_mm (rest and current positions)
std::string particles_csv(const Model& m, const State& s);
void write_particles_csv(const std::string& path, const Model& m, const State& s);
// keys: steps, sim_time_s, wall_time_s, kinetic_energy_J, max_speed_m_s, volume_error, warnings
void write_summary_json(const std::string& path, const Model& m, const RunResult& r);
// The current surface of a component as a mesh over its own vertices [m].
TriMesh component_surface_mesh(const Model& m, const State& s, int component);
// OBJ in millimetres.
void write_surface_obj(const std::string& path, const TriMesh& mesh);

}  // namespace ps
