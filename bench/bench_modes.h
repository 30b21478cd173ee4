// Plain (untimed) modes of prostatesim_bench and helpers shared by the benchmark files.
#pragma once
#include <cstdint>
#include <string>

#include "engine/step/simulation.h"

namespace ps::detail {
// engine/step/shape_memory.cpp: the stage's x86-64-baseline build, which add_shape_memory_forces()
// runs on CPUs without AVX (declared here only: nothing outside the bench should pick a build).
void add_shape_memory_forces_baseline(const Model& m, State& s);
}  // namespace ps::detail

namespace ps::bench {

int print_info();                                   // modes.cpp
int run_steps(const std::string& scene, int steps); // modes.cpp
int verify_shape_memory();                          // modes.cpp
int stable_dt_study(int steps);                     // stable_dt.cpp
int soak(int substeps);                             // soak.cpp
int stable_dt_profile(const std::string& file);     // stable_dt_profile.cpp
int fast_error(const std::string& scene, int substeps, int mass_scaling, int triplets, double duration,
               int ref_substeps, double fast_nu = 0.0, int fast_pressure = -1,
               int pressure_iterations = 0, double fast_sleep_wake = -1.0,
               int fast_multirate = -1, double fast_dt_ms = -1.0, const std::string& ref_file = "");  // fast_error.cpp
int run_ticks(const std::string& file, int ticks);  // tick_mode.cpp
int realtime_loop(double wall_s);                   // realtime_loop.cpp
int speed_trace(const std::string& file, const std::string& script, int substeps, int mass_scaling);  // speed_trace.cpp
int tick_trace(const std::string& file, const std::string& script, double window_ms);  // tick_trace.cpp

// The shape-memory stage exactly as it was before the performance work (reference_shape_memory.cpp):
// kept so one binary measures the speed-up and checks the optimised stage against it.
void reference_add_shape_memory_forces(const Model& m, State& s);

// Wall time spent in each pipeline stage, summed over timed_step() calls [ns].
struct StageTimes {
  int64_t ns[24] = {};  // indexed by Stage (engine/step/simulation.h)
};
// Simulation::step() for a scene without tools, stage by stage with a clock read between
// stages (~20 ns each). Returns false on a fault, like step().
bool timed_step(Simulation& sim, double dt, StageTimes& times);

}  // namespace ps::bench
