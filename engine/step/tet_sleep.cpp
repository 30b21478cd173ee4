// Sleeping tissue (Model::sleep, solver.sleep; docs/model.md "Sleeping tissue"): "skip what a
// scene doesn't need". Most of a scene's fat is far from the needle and the probe and, once the
// scene has settled, at rest; its elements would be evaluated every substep for forces that
// balance. A particle that has been balanced (|f| / m below sleep_accel) and at rest (|v| below
// sleep_speed) for hold_ticks tick ends falls asleep: it is no longer integrated and keeps v = 0.
// An element whose four nodes all sleep (or are fixed) is held: it is not evaluated; its volume
// shares and its forces on its nodes, taken when it was held, stand in for it (State::tet_held_vol,
// tet_held_f), so the pressure of an awake node and the balance of a sleeping one are complete.
// A sleeping particle wakes in the substep a load reaches it:
//   - its unbalanced force, f (the evaluated elements, gravity, shells, tools) plus the held
//     elements' force, exceeds m x wake_accel (the wake threshold is 4 x the sleep threshold, so
//     a particle that just fell asleep does not wake again on its own residual), or
//   - a constraint or a tool moved it during the substep.
// Its error: a sleeping particle stands where it fell asleep while its unbalanced force is below
// m x wake_accel, i.e. off its equilibrium by at most about that force over its local stiffness;
// bench --fast-error measures the effect on the needle force and the prostate against the
// converged run. Deterministic: the decisions read only the state, in particle order.
// No allocation: every array is sized at make_state.
#include "engine/step/stages.h"

namespace ps {

void rebuild_tet_sleep(const Model& m, State& s) {
  const TetElements& te = m.tets;
  const int nt = te.count();
  const int nn = static_cast<int>(te.nodes.size());
  const uint8_t* role = m.sleep.role.data();
  const uint8_t* asleep = s.asleep.data();
  const int* vv = te.v.data();
  auto still = [&](int p) { return asleep[p] || role[p] == TetSleep::kFixed; };
  // the evaluated elements (an awake node) ascending, then the held ones ascending
  int* order = s.tet_order.data();
  int na = 0;
  for (int t = 0; t < nt; ++t) {
    const int* v = vv + 4 * t;
    if (!(still(v[0]) && still(v[1]) && still(v[2]) && still(v[3]))) order[na++] = t;
  }
  int k = na;
  for (int t = 0; t < nt; ++t) {
    const int* v = vv + 4 * t;
    if (still(v[0]) && still(v[1]) && still(v[2]) && still(v[3])) order[k++] = t;
  }
  s.tet_awake_count = na;
  // the held elements' volume shares (their nodes do not move while they are held)
  const Vec3* x = s.x.data();
  double* held_vol = s.tet_held_vol.data();
  for (int a = 0; a < nn; ++a) held_vol[a] = 0.0;
  add_tet_node_volumes(te, x, order + na, nt - na, held_vol);
  // their force now, at the node pressures of every element's current volume
  double* p = s.tet_node_vol.data();
  for (int a = 0; a < nn; ++a) p[a] = held_vol[a];
  add_tet_node_volumes(te, x, order, na, p);
  tet_node_pressures(te, p);
  Vec3* held_f = s.tet_held_f.data();
  for (int q = 0, n = m.particle_count(); q < n; ++q) held_f[q].setZero();
  add_tet_element_forces(te, x, p, order + na, nt - na, held_f);
}

void update_tet_sleep(const Model& m, State& s, bool tick_end) {
  const TetSleep& sl = m.sleep;
  const int n = m.particle_count();
  const uint8_t* role = sl.role.data();
  const double* inv_mass = m.inv_mass.data();
  uint8_t* asleep = s.asleep.data();
  uint16_t* quiet = s.quiet_ticks.data();
  const Vec3* x = s.x.data();
  const Vec3* x_prev = s.x_prev.data();
  const Vec3* f = s.f.data();
  const Vec3* held_f = s.tet_held_f.data();
  Vec3* v = s.v.data();
  const double wake2 = sl.wake_accel * sl.wake_accel, sleep2 = sl.sleep_accel * sl.sleep_accel;
  const double speed2 = sl.sleep_speed * sl.sleep_speed;
  bool changed = false;
  for (int p = 0; p < n; ++p) {
    if (role[p] != TetSleep::kMaySleep) continue;
    const double im = inv_mass[p];
    if (asleep[p]) {
      const Vec3 r = f[p] + held_f[p];  // unbalanced force [N]
      if (im * im * r.squaredNorm() > wake2 || x[p] != x_prev[p]) {
        asleep[p] = 0;
        quiet[p] = 0;
        changed = true;
      }
    } else if (tick_end) {
      // an awake particle's elements are all evaluated: f is its whole unbalanced force
      if (v[p].squaredNorm() > speed2 || im * im * f[p].squaredNorm() > sleep2) {
        quiet[p] = 0;
      } else if (++quiet[p] >= sl.hold_ticks) {
        asleep[p] = 1;
        quiet[p] = 0;
        v[p].setZero();
        changed = true;
      }
    }
  }
  if (changed) rebuild_tet_sleep(m, s);
}

}  // namespace ps
