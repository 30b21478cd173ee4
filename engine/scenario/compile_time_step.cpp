// Time-step stage of compile_scenario: the largest stable substep of the explicit scheme
// (estimate_stable_dt), the multi-rate partition of the tet elements, selective mass scaling, and
// the substep count raised (or the scene refused) so each substep is within 90% of the limit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "engine/model/shell_elements.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/compile_stages.h"
#include "engine/scenario/material_models.h"
#include "engine/scenario/size_estimate.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"

namespace ps {

// The explicit step's limit for a mode of frequency omega [rad/s] with stiffness-proportional
// damping beta [s] (forces at x + beta v): (2 / omega)(sqrt(1 + zeta^2) - zeta), zeta = beta omega / 2
// (central differences with Rayleigh damping, Belytschko, Liu & Moran, "Nonlinear finite elements",
// 6.3). beta = 0 gives 2 / omega.
namespace {
double damped_stable_step(double omega, double beta) {
  const double zeta = 0.5 * beta * omega;
  return 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
}
}  // namespace

double estimate_stable_dt(const Model& m, TetPass pass) {
  const int n = m.particle_count();
  // no elastic term: nothing limits the step (with one whose particles are all fixed the
  // iteration below finds no force and gives the same)
  bool any = false;
  for (const MaterialModelDesc* model : material_models()) any |= model->present(m);
  if (!any) return std::numeric_limits<double>::infinity();
  State s = make_state(m);
  std::vector<Vec3> v(n), w(n);
  std::mt19937_64 rng(12345);  // fixed seed: the estimate is reproducible
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  auto free_axis = [&](int p, int a) { return m.inv_mass[p] > 0.0 && !(m.locked_axes[p] & (1u << a)); };
  for (int p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) v[p][a] = free_axis(p, a) ? U(rng) : 0.0;
  double scale = 0.0;
  for (const Vec3& r : m.rest_pos) scale = std::max(scale, r.cwiseAbs().maxCoeff());
  double lambda = 0.0;
  for (int it = 0; it < 60; ++it) {
    double norm = 0.0;
    for (const Vec3& x : v) norm += x.squaredNorm();
    norm = std::sqrt(norm);
    if (!(norm > 0.0)) break;
    const double eps = 1e-7 * std::max(scale, 1e-3) / norm;
    for (int p = 0; p < n; ++p) { s.x[p] = m.rest_pos[p] + eps * v[p]; s.f[p].setZero(); }
    for (const MaterialModelDesc* model : material_models()) model->add_forces(m, s, pass);
    double wn = 0.0;
    for (int p = 0; p < n; ++p) {
      for (int a = 0; a < 3; ++a) w[p][a] = free_axis(p, a) ? -s.f[p][a] * m.inv_mass[p] / eps : 0.0;
      wn += w[p].squaredNorm();
    }
    wn = std::sqrt(wn);
    lambda = wn / norm;  // |A v| / |v| -> |lambda_max|
    if (!(wn > 0.0)) break;
    for (int p = 0; p < n; ++p) v[p] = w[p] / wn;  // renormalise: no overflow
  }
  return lambda > 0.0 ? damped_stable_step(std::sqrt(lambda), m.stiffness_damping) : std::numeric_limits<double>::infinity();
}

namespace {
// Model::added_inertia and largest_inertia_factor from the inertial masses against the physical
// ones: whatever added them (the substep's scaling, the multi-rate tick's, or both).
void tally_added_inertia(Model& m) {
  m.added_inertia = 0.0;
  m.largest_inertia_factor = 1.0;
  for (int p = 0, n = m.particle_count(); p < n; ++p) {
    if (m.inv_mass[p] == 0.0 || !(m.mass[p] > 0.0)) continue;
    const double inertial = 1.0 / m.inv_mass[p];  // [kg]
    if (inertial <= m.mass[p]) continue;
    m.added_inertia += inertial - m.mass[p];
    m.largest_inertia_factor = std::max(m.largest_inertia_factor, inertial / m.mass[p]);
  }
}
}  // namespace

// Selective mass scaling (a standard device of explicit dynamics): the particles whose
// stiffness-to-mass ratio sets the stable substep get more inertial mass, so that the file's
// substep h = dt / substeps is at most `margin` of the new limit. Gravity keeps acting on the
// physical mass (forces.cpp reads Model::mass); the implicit damping v /= (1 + c h) is
// proportional to the inertial mass, so each scaled particle's damping rate is divided by the
// same factor and its damping force c m v is unchanged. Which particles: a per-particle stiffness
// proxy d_p (k_e of its own attractor plus the shares of the attractors it enters, w^2 k_e, and,
// for strain clusters, (2 mu V + lambda V) |g|^2 + k_r) gives m_p' = max(m_p, A d_p h^2 / 4); the
// amplification A starts at 2 and grows until the power-iteration estimate of the whole scene
// (any force stage, estimate_stable_dt) admits h. Deterministic; compile time only.
void scale_inertia_to_substep(Model& m, double margin) {
  const int n = m.particle_count();
  const double h = m.dt / m.substeps;
  if (!(m.stable_dt_estimate * margin < h)) return;
  // with multi-rate only the fast group sets the substep: the slow elements' stiffness is left
  // out, or the soft bulk would get inertia it does not need
  const std::vector<double> d = stiffness_proxy(m, m.tets.multirate());
  const std::vector<double> inv_mass0 = m.inv_mass, damping0 = m.damping;
  double A = 2.0;
  for (int it = 0; it < 40 && m.stable_dt_estimate * margin < h; ++it) {
    const double want = h / margin;  // the limit the estimate must reach [s]
    for (int p = 0; p < n; ++p) {
      m.inv_mass[p] = inv_mass0[p];
      m.damping[p] = damping0[p];
      if (inv_mass0[p] == 0.0 || d[p] == 0.0) continue;
      // inertial mass for omega_p want <= 2 [kg] (the estimate then sees the damping, and A grows
      // until it admits h)
      const double need = A * d[p] * want * want / 4.0;
      if (need * inv_mass0[p] <= 1.0) continue;
      m.inv_mass[p] = 1.0 / need;
      m.damping[p] = damping0[p] * need * inv_mass0[p] > 0.0 ? damping0[p] / (need * inv_mass0[p]) : 0.0;
    }
    m.stable_dt_estimate = estimate_stable_dt(m, m.tets.multirate() ? TetPass::FastOnly : TetPass::All);
    const double r = want / m.stable_dt_estimate;
    A *= std::max(1.05, r * r);
  }
  tally_added_inertia(m);
}

// Per-particle stiffness proxy d_p [N/m], term by term in the order of the material models
// (material_models.h: each model's add_stiffness says what its term contributes). A lone particle
// on a spring d_p has omega^2 = d_p / m_p.
std::vector<double> stiffness_proxy(const Model& m, bool fast_only, ProxyForm form) {
  std::vector<double> d(m.particle_count(), 0.0);
  for (const MaterialModelDesc* model : material_models()) model->add_stiffness(m, fast_only, form, d);
  return d;
}

namespace {

// The tet elements reordered fast first (an element is slow when its four particles are), each
// group in its original order (deterministic), from the arrays as they were before any partition
// (orig); sets TetElements::fast_count.
struct TetOrder {
  std::vector<int> v;
  std::vector<double> g, vol0, mu;
};

void order_tet_rates(TetElements& te, const TetOrder& orig, const std::vector<uint8_t>& slow) {
  const int nt = te.count();
  auto is_slow = [&](int t) {
    const int* v = &orig.v[4 * t];
    return slow[v[0]] && slow[v[1]] && slow[v[2]] && slow[v[3]];
  };
  int k = 0;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) te.fast_count = k;
    for (int t = 0; t < nt; ++t) {
      if (is_slow(t) != (pass == 1)) continue;
      for (int i = 0; i < 4; ++i) te.v[4 * k + i] = orig.v[4 * t + i];
      for (int i = 0; i < 9; ++i) te.g[9 * k + i] = orig.g[9 * t + i];
      te.vol0[k] = orig.vol0[t];
      te.mu[k] = orig.mu[t];
      ++k;
    }
  }
}

void restore_tet_order(TetElements& te, const TetOrder& orig) {
  te.v = orig.v;
  te.g = orig.g;
  te.vol0 = orig.vol0;
  te.mu = orig.mu;
  te.fast_count = te.count();
}

std::string slow_group_line(const TetElements& te, double slow_limit) {
  char b[200];
  std::snprintf(b, sizeof b, "multirate: %d of %d tet elements once per tick (slow group's stable step %.3g ms)",
                te.count() - te.fast_count, te.count(), slow_limit * 1e3);
  return b;
}

}  // namespace

std::string partition_tet_rates(Model& m, double margin) {
  TetElements& te = m.tets;
  const int n = m.particle_count(), nt = te.count();
  if (nt == 0) return {};
  const std::vector<double> d = stiffness_proxy(m, false, ProxyForm::ElementBound);
  // a particle's own limit 2 / omega_p with omega_p^2 = d_p / m_p (inertial mass); fixed ones never limit
  std::vector<double> limit(n, std::numeric_limits<double>::infinity());
  for (int p = 0; p < n; ++p)
    if (m.inv_mass[p] > 0.0 && d[p] > 0.0) limit[p] = damped_stable_step(std::sqrt(d[p] * m.inv_mass[p]), m.stiffness_damping);
  std::vector<uint8_t> slow(n, 0);
  for (int p = 0; p < n; ++p) slow[p] = margin * limit[p] >= m.dt;
  const TetOrder orig{te.v, te.g, te.vol0, te.mu};
  for (int round = 0; round < 12; ++round) {
    order_tet_rates(te, orig, slow);
    if (te.fast_count == nt) return "multirate: no tet element admits the whole tick; every element runs every substep";
    const double slow_limit = estimate_stable_dt(m, TetPass::SlowOnly);
    if (margin * slow_limit >= m.dt) return slow_group_line(te, slow_limit);
    // the estimate does not confirm it: the stiffest tenth of the slow particles become fast
    std::vector<std::pair<double, int>> by_limit;
    for (int p = 0; p < n; ++p)
      if (slow[p]) by_limit.emplace_back(limit[p], p);
    std::sort(by_limit.begin(), by_limit.end());
    const size_t drop = std::max<size_t>(1, by_limit.size() / 10);
    for (size_t i = 0; i < drop && i < by_limit.size(); ++i) slow[by_limit[i].second] = 0;
  }
  // give up: every element every substep
  restore_tet_order(te, orig);
  return "multirate: the slow group's estimate never admitted the tick; every element runs every substep";
}

// Multi-rate inertia (solver.multirate_inertia F > 1). A particle whose own stable step (the
// stiffness proxy's 2 / omega_p) falls a little short of the whole tick gets inertial mass, at
// most F times its own, so that its elements can join the slow group (once per tick) instead of
// running every substep. It picks the soft bulk (the fat at a 2 ms tick) and leaves alone what
// would need far more (the prostate's shear, the walls' bending), which stays in the fast group
// at the substep. Never the walls' vertices nor the implicit pressure's nodes: their motion is
// what the trainee sees and feels (the needle's tenting and puncture, the gland), and their
// inertia would act on every substep. Gravity keeps the physical mass and the damping force
// c m v is kept, as in scale_inertia_to_substep.
// How much: the inertia for which the proxy admits the tick times an amplification a (the
// partition's own test on the proxy is >=, a = 1.1 keeps it clear of rounding), raised along a
// ladder until the power-iteration estimate of the slow group admits the tick. A particle counts
// as slow only where its proxy does: counting more (the proxy's need relaxed, relying on the
// estimate alone) blows up the default scenes within 0.3 s at a 2 ms tick, at a wall's vertex and
// in the fat (the impulse method's resonance). A particle that ends in no slow element keeps its
// own mass. Returns false (the model as it came in) when no rung admits the tick.
bool partition_tet_rates_with_inertia(Model& m, double margin, double max_factor, std::vector<std::string>& notes) {
  TetElements& te = m.tets;
  const int n = m.particle_count(), nt = te.count();
  if (nt == 0) return false;
  // the gate: the element bound (a particle counts as slow only where it admits the tick, with up
  // to max_factor of inertia); the inertia itself: the diagonal, what the particle needs
  const std::vector<double> gate = stiffness_proxy(m, false, ProxyForm::ElementBound);
  const std::vector<double> d = stiffness_proxy(m, false, ProxyForm::Diagonal);
  const double want = m.dt / margin;  // the per-particle limit the partition asks for [s]
  const double beta = m.stiffness_damping;  // [s]
  std::vector<uint8_t> excluded(n, 0);
  for (int v : m.shells.tri) excluded[v] = 1;
  for (size_t a = 0; a < te.nodes.size(); ++a)
    if (te.node_kappa[a] > 0.0 && te.node_kappa_explicit[a] == 0.0) excluded[te.nodes[a]] = 1;
  const std::vector<double> inv_mass0 = m.inv_mass, damping0 = m.damping;
  const TetOrder orig{te.v, te.g, te.vol0, te.mu};
  std::vector<uint8_t> slow(n, 0);
  // Rungs, tried in order until the slow group's estimate admits the tick: first the bound's gate
  // at 1.1 with the inertia sized on the diagonal, amplified step by step (at most max_factor);
  // then the gate narrowed with the inertia sized on the bound (a last resort: the bound reads the
  // fat's nodal pressure ~8x stiffer than the diagonal, so it adds far more inertia).
  struct Rung {
    double gate, size;
    bool on_diagonal;
  };
  static constexpr Rung kRungs[] = {{1.1, 1.1, true},   {1.1, 1.25, true},  {1.1, 1.4, true},   {1.1, 1.6, true},
                                    {1.1, 2.0, true},   {1.1, 2.5, true},   {1.1, 3.2, true},   {1.1, 4.0, true},
                                    {1.1, 5.0, true},   {1.1, 6.4, true},   {1.1, 8.0, true},   {1.1, 16.0, true},
                                    {1.1, 1.1, false},  {1.25, 1.25, false}, {1.4, 1.4, false}, {1.6, 1.6, false},
                                    {2.0, 2.0, false}};
  for (const Rung& rung : kRungs) {
    for (int p = 0; p < n; ++p) {
      m.inv_mass[p] = inv_mass0[p];
      m.damping[p] = damping0[p];
      const double im = inv_mass0[p];
      if (im == 0.0 || gate[p] == 0.0) { slow[p] = 1; continue; }  // fixed, or no stiffness: never limits
      // inertial mass for the proxy to admit the tick / own mass: the damped limit
      // (2 / w)(sqrt(1 + z^2) - z), z = beta w / 2, reaches `want` at w = 2 / sqrt(want (want + 2 beta))
      const double w2 = want * (want + 2.0 * beta) / 4.0 * im;
      if (gate[p] * w2 <= 1.0) { slow[p] = 1; continue; }
      slow[p] = !excluded[p] && rung.gate * gate[p] * w2 <= max_factor;
      const double factor = std::clamp(rung.size * (rung.on_diagonal ? d[p] : gate[p]) * w2, 1.0, max_factor);
      if (slow[p]) {
        m.inv_mass[p] = im / factor;
        m.damping[p] = damping0[p] / factor;
      }
    }
    order_tet_rates(te, orig, slow);
    if (te.fast_count == nt) continue;
    const double slow_limit = estimate_stable_dt(m, TetPass::SlowOnly);
    if (!(margin * slow_limit >= m.dt)) continue;
    // admitted: the inertia stays only on the vertices of slow elements
    std::vector<uint8_t> in_slow(n, 0);
    for (int k = 4 * te.fast_count; k < 4 * nt; ++k) in_slow[te.v[k]] = 1;
    std::vector<double> kept(m.components.size(), 0.0);  // [kg]
    double total = 0.0;
    for (int p = 0; p < n; ++p) {
      if (m.inv_mass[p] == inv_mass0[p]) continue;
      if (!in_slow[p]) {
        m.inv_mass[p] = inv_mass0[p];
        m.damping[p] = damping0[p];
        continue;
      }
      const double add = 1.0 / m.inv_mass[p] - 1.0 / inv_mass0[p];
      total += add;
      kept[static_cast<size_t>(m.component_of[p])] += add;
    }
    notes.push_back(slow_group_line(te, slow_limit));
    if (!(total > 0.0)) return true;
    char b[160];
    std::snprintf(b, sizeof b, "multirate inertia: %.4g g added for the slow group (%.3g x the %s's need", total * 1e3, rung.size,
                  rung.on_diagonal ? "stiffness diagonal" : "element bound");
    std::string line = b;
    for (size_t c = 0; c < kept.size(); ++c) {
      if (!(kept[c] > 0.0)) continue;
      std::snprintf(b, sizeof b, "; %s %.4g g", m.components[c].name.c_str(), kept[c] * 1e3);
      line += b;
    }
    notes.push_back(line + ")");
    return true;
  }
  m.inv_mass = inv_mass0;
  m.damping = damping0;
  restore_tet_order(te, orig);
  return false;
}

void compile_time_step(const ScenarioSpec& spec, Model& m, CompileWork& work) {
  auto& warnings = work.warnings;
  auto& notes = work.notes;
  // stability: raise substeps so each substep is at most 90% of the estimated limit, or (with
  // solver.mass_scaling) add inertia to the particles that set the limit
  const bool tick_inertia = spec.multirate && spec.multirate_inertia > 1.0 &&
                            partition_tet_rates_with_inertia(m, 0.9, spec.multirate_inertia, notes);
  if (spec.multirate && !tick_inertia) notes.push_back(partition_tet_rates(m, 0.9));
  // with multi-rate the substep is set by the fast group (the held slow force is a constant
  // within a tick); the slow group was checked against the tick above
  m.stable_dt_estimate = estimate_stable_dt(m, m.tets.multirate() ? TetPass::FastOnly : TetPass::All);
  if (spec.mass_scaling) scale_inertia_to_substep(m, 0.9);
  if (tick_inertia) tally_added_inertia(m);  // also where the substep needed none
  const double h = m.dt / m.substeps;
  if (h > 0.9 * m.stable_dt_estimate) {
    // In double first: a stiffness like young_kpa 1e9 gives a stable step so small that the count
    // overflows an int (wrapped, it would run "successfully" with 0 steps).
    const double need_d = m.dt / (0.9 * m.stable_dt_estimate);
    if (!(need_d <= kMaxSubstepsPerTick)) {
      const MaterialSpec* stiff = nullptr;
      for (const auto& mat : spec.materials) {
        const double e = mat.young.value_or(0.0), se = stiff ? stiff->young.value_or(0.0) : -1.0;
        if (!stiff || e > se) stiff = &mat;
      }
      char b[256];
      std::snprintf(b, sizeof b,
                    "a tick of %g ms would need %.3g substeps for stability (stable substep %.3g s; limit %d "
                    "substeps per tick): the scene is too stiff for its tick; lower young_kpa / k_e_n_m of the "
                    "stiffest material or time.dt_ms",
                    m.dt * 1e3, need_d, m.stable_dt_estimate, kMaxSubstepsPerTick);
      throw InputError(spec.file, stiff ? stiff->loc.line : 0,
                       stiff ? "materials." + stiff->name + ".young_kpa" : std::string("time.dt_ms"), b);
    }
    const int need = static_cast<int>(std::ceil(need_d));
    warnings.push_back("substeps raised from " + std::to_string(m.substeps) + " to " + std::to_string(need) +
                       ": substep " + std::to_string(h) + " s exceeds 90% of the stable limit " +
                       std::to_string(m.stable_dt_estimate) + " s");
    m.substeps = need;
  }
}

}  // namespace ps
