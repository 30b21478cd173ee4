// Sleeping-tissue stage of compile_scenario (solver.sleep; Model::sleep, engine/step/tet_sleep.cpp
// says how the step uses it): which particles may sleep, and the thresholds.
#include <cmath>
#include <cstdio>

#include "engine/scenario/compile_stages.h"
#include "engine/util/error.h"

namespace ps {

void compile_sleep(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  m.sleep = TetSleep{};
  if (!spec.sleep) return;
  const TetElements& te = m.tets;
  const int n = m.particle_count();
  if (te.multirate())  // the reader refuses it in a file; this is a spec built in code
    throw CompileError("solver.sleep cannot be combined with solver.multirate (both choose which tet elements run)");
  if (te.count() == 0) {
    work.notes.push_back("sleep: no tet element in the scene; solver.sleep has nothing to put to sleep");
    return;
  }
  // Only a tet node whose motion is the tet elements' and the integrator's alone may sleep. Left
  // awake: rigid and kinematic particles (their body places them), particles held on some but
  // not every axis or imposed (constraints move them), volume-constrained surfaces (the
  // projection moves them), the implicit pressure's support (its solve moves them), particles
  // with a shape-memory, strain-cluster or shell force of their own. The walls stay awake
  // because letting the rectal wall sleep was measured to cost accuracy where the needle
  // crosses it: on the biopsy insertion the lesion target's error went from 0.72 to 1.01 mm and
  // the capsule puncture depth from 1.1 to 2.0 mm off (bench --fast-error, wake 0.1 m/s^2).
  std::vector<uint8_t> keep_awake(n, 0);
  for (const ImposedDisplacement& im : m.imposed)
    for (int p : im.particles) keep_awake[p] = 1;
  for (const Surface& surf : m.surfaces)
    if (surf.volume_constrained)
      for (int p : surf.vertices) keep_awake[p] = 1;
  for (int p : m.tet_pressure.particles) keep_awake[p] = 1;
  for (int p : m.strain.member) keep_awake[p] = 1;
  for (int p : m.shells.tri) keep_awake[p] = 1;
  std::vector<uint8_t> role(n, TetSleep::kAwake);
  int eligible = 0, fixed = 0;
  for (int p = 0; p < n; ++p) {
    if (te.node_slot[p] < 0 || keep_awake[p]) continue;
    if (m.inv_mass[p] == 0.0) continue;
    if (m.locked_axes[p] == 7) {
      role[p] = TetSleep::kFixed;
      ++fixed;
    } else if (m.locked_axes[p] == 0 && !(m.shape_memory[p] && m.k_e[p] > 0.0) &&
               !te.node_implicit[te.node_slot[p]]) {
      role[p] = TetSleep::kMaySleep;
      ++eligible;
    }
  }
  m.sleep.role = std::move(role);
  m.sleep.eligible_count = eligible;
  m.sleep.wake_accel = spec.sleep_wake_accel;
  // 4x hysteresis: a particle that has just fallen asleep with its residual at the sleep
  // threshold does not wake again on it
  m.sleep.sleep_accel = 0.25 * spec.sleep_wake_accel;
  // at rest: no faster than the balanced residual accelerates it over 10 ms
  m.sleep.sleep_speed = m.sleep.sleep_accel * 0.01;
  // balanced and at rest for 20 ms of tick ends (at least 2)
  m.sleep.hold_ticks = std::max(2, static_cast<int>(std::ceil(0.02 / m.dt - 1e-9)));
  char b[224];
  std::snprintf(b, sizeof b,
                "sleep: %d of %d particles may sleep (%d fixed count as asleep); wake at %.3g m/s^2, sleep below %.3g m/s^2 "
                "and %.3g mm/s for %d ticks",
                eligible, n, fixed, m.sleep.wake_accel, m.sleep.sleep_accel, m.sleep.sleep_speed * 1e3, m.sleep.hold_ticks);
  work.notes.push_back(b);
}

}  // namespace ps
