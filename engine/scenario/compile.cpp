#include "engine/scenario/compile.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "engine/anatomy/scene_regions.h"
#include "engine/model/discrete_coordinates.h"
#include "engine/model/material.h"
#include "engine/model/shell_elements.h"
#include "engine/model/strain_clusters.h"
#include "engine/model/tet_elements.h"
#include "engine/scenario/particle_set.h"
#include "engine/scenario/shape_mesh.h"
#include "engine/scenario/size_estimate.h"
#include "engine/step/stages.h"
#include "engine/util/error.h"
#include "engine/util/spatial_grid.h"

namespace ps {

namespace {

const MaterialSpec& find_material(const ScenarioSpec& spec, const std::string& name) {
  for (const auto& m : spec.materials)
    if (m.name == name) return m;
  throw std::logic_error("material checked by the parser");
}

ParticleSet build_particles(const ComponentSpec& c, const std::string& file, std::vector<std::string>* warnings) {
  const ShapeSpec& s = c.shape;
  switch (s.kind) {
    case ShapeSpec::Box: {
      const Vec3 size = s.max - s.min;
      if (size.minCoeff() < c.spacing)
        throw InputError(file, c.loc.line, "components." + c.name + ".spacing_mm",
                         "spacing is larger than the smallest box side");
      return box_particles(s.min, s.max, c.spacing, c.volumetric);
    }
    case ShapeSpec::Cylinder: {
      if (2 * s.radius < c.spacing || s.length < c.spacing)
        throw InputError(file, c.loc.line, "components." + c.name + ".spacing_mm",
                         "spacing is larger than the cylinder diameter or length");
      const TriMesh surf = cylinder_surface(s.base, s.axis, s.radius, s.length, c.spacing);
      if (!c.volumetric) return surface_particles(surf);
      const Vec3 ax = s.axis.normalized();
      auto radial = [&](const Vec3& p) {
        const Vec3 d = p - s.base;
        return std::pair{(d - d.dot(ax) * ax).norm(), d.dot(ax)};
      };
      return volumetric_particles(
          surf, c.spacing,
          [&](const Vec3& p) {
            auto [r, z] = radial(p);
            return r < s.radius && z > 0 && z < s.length;
          },
          [&](const Vec3& p) {
            auto [r, z] = radial(p);
            return std::min({s.radius - r, z, s.length - z});
          });
    }
    case ShapeSpec::Mesh: return particles_from_mesh(c, file, warnings);
  }
  return {};
}

struct Selection {
  std::vector<int> particles;
};

}  // namespace

std::vector<double> stiffness_proxy(const Model& m, bool fast_only = false);

double estimate_stable_dt(const Model& m, TetPass pass) {
  const int n = m.particle_count();
  const bool others = pass != TetPass::SlowOnly;  // the other force stages
  bool any = false;
  for (int p = 0; p < n; ++p)
    any |= ((m.shape_memory[p] || (!m.tets.node_slot.empty() && m.tets.node_slot[p] >= 0)) && m.inv_mass[p] > 0.0);
  any |= m.strain.count() > 0;
  any |= m.shells.triangle_count() > 0;
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
    if (others) add_shape_memory_forces(m, s);
    if (others && m.strain.count() > 0) add_strain_memory_forces(m, s, 50);  // R converged at each probe
    if (m.tets.count() > 0) add_tet_elastic_forces(m, s, pass);
    if (others && m.shells.triangle_count() > 0) add_shell_elastic_forces(m, s);
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
  return lambda > 0.0 ? 2.0 / std::sqrt(lambda) : std::numeric_limits<double>::infinity();
}

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
    m.added_inertia = 0.0;
    m.largest_inertia_factor = 1.0;
    for (int p = 0; p < n; ++p) {
      m.inv_mass[p] = inv_mass0[p];
      m.damping[p] = damping0[p];
      if (inv_mass0[p] == 0.0 || d[p] == 0.0) continue;
      const double need = A * d[p] * want * want / 4.0;  // inertial mass for omega_p want <= 2 [kg]
      if (need * inv_mass0[p] <= 1.0) continue;
      m.inv_mass[p] = 1.0 / need;
      m.damping[p] = damping0[p] * need * inv_mass0[p] > 0.0 ? damping0[p] / (need * inv_mass0[p]) : 0.0;
      m.added_inertia += need - m.mass[p];
      m.largest_inertia_factor = std::max(m.largest_inertia_factor, need * inv_mass0[p]);
    }
    m.stable_dt_estimate = estimate_stable_dt(m, m.tets.multirate() ? TetPass::FastOnly : TetPass::All);
    const double r = want / m.stable_dt_estimate;
    A *= std::max(1.05, r * r);
  }
}

// Per-particle stiffness proxy d_p [N/m]: k_e of its own attractor plus the shares of the
// attractors it enters (w^2 k_e), for strain clusters (2 mu V + lambda V) |g|^2 + k_r, for tet
// elements V0 (mu + kappa) |g_i|^2 (the diagonals of the stiffness). A lone particle on a spring
// d_p has omega^2 = d_p / m_p.
std::vector<double> stiffness_proxy(const Model& m, bool fast_only) {
  const int n = m.particle_count();
  std::vector<double> d(n, 0.0);
  for (int p = 0; p < n; ++p) {
    if (!m.shape_memory[p]) continue;
    d[p] += m.k_e[p];
    for (int a = m.nbr_start[p]; a < m.nbr_start[p + 1]; ++a) d[m.nbr[a]] += m.k_e[p] * m.nbr_w[a] * m.nbr_w[a];
  }
  const StrainClusters& sc = m.strain;
  for (int c = 0; c < sc.count(); ++c)
    for (int i = sc.start[c]; i < sc.start[c + 1]; ++i)
      d[sc.member[i]] += (sc.mu2v[c] + sc.k_v[c]) * sc.g[i].squaredNorm() + sc.k_r[c];
  // tet elements: V0 (mu + kappa) |g_i|^2 per vertex (the diagonal of the element's stiffness)
  // (fast_only: the multi-rate fast group's elements, those that set the substep)
  const TetElements& te = m.tets;
  for (int t = 0, nt = fast_only ? te.fast_count : te.count(); t < nt; ++t) {
    const double* g = &te.g[9 * t];
    const Vec3 g1(g[0], g[1], g[2]), g2(g[3], g[4], g[5]), g3(g[6], g[7], g[8]), g0 = -(g1 + g2 + g3);
    const Vec3 gi[4] = {g0, g1, g2, g3};
    for (int i = 0; i < 4; ++i) {
      const int p = te.v[4 * t + i];
      d[p] += te.vol0[t] * (te.mu[t] + te.node_kappa[te.node_slot[p]]) * gi[i].squaredNorm();
    }
  }
  // shell triangles: A0 t (2 mu + lambda) |g_i|^2 per vertex (g_1, g_2 the rows of Dm^-1, g_0 minus
  // their sum); hinges: k_h |d theta / d x_i|^2 at rest
  const ShellElements& sh = m.shells;
  for (int t = 0; t < sh.triangle_count(); ++t) {
    const double* B = &sh.bm[4 * t];
    const double k = sh.area_t[t] * (2.0 * sh.mu[t] + sh.lambda[t]);
    const double g1 = B[0] * B[0] + B[1] * B[1], g2 = B[2] * B[2] + B[3] * B[3];
    const double g0 = (B[0] + B[2]) * (B[0] + B[2]) + (B[1] + B[3]) * (B[1] + B[3]);
    d[sh.tri[3 * t]] += k * g0;
    d[sh.tri[3 * t + 1]] += k * g1;
    d[sh.tri[3 * t + 2]] += k * g2;
  }
  for (int h = 0; h < sh.hinge_count(); ++h) {
    const int* v = &sh.hinge[4 * h];
    Vec3 g[4];
    hinge_angle(m.rest_pos[v[0]], m.rest_pos[v[1]], m.rest_pos[v[2]], m.rest_pos[v[3]], g);
    for (int i = 0; i < 4; ++i) d[v[i]] += sh.k_hinge[h] * g[i].squaredNorm();
  }
  return d;
}

std::string partition_tet_rates(Model& m, double margin) {
  TetElements& te = m.tets;
  const int n = m.particle_count(), nt = te.count();
  if (nt == 0) return {};
  const std::vector<double> d = stiffness_proxy(m);
  // a particle's own limit 2 / omega_p with omega_p^2 = d_p / m_p (inertial mass); fixed ones never limit
  std::vector<double> limit(n, std::numeric_limits<double>::infinity());
  for (int p = 0; p < n; ++p)
    if (m.inv_mass[p] > 0.0 && d[p] > 0.0) limit[p] = 2.0 / std::sqrt(d[p] * m.inv_mass[p]);
  std::vector<uint8_t> slow(n, 0);
  for (int p = 0; p < n; ++p) slow[p] = margin * limit[p] >= m.dt;
  const std::vector<int> v0 = te.v;
  const std::vector<double> g0 = te.g, vol00 = te.vol0, mu0 = te.mu;
  std::string line;
  for (int round = 0; round < 12; ++round) {
    // order: fast elements (any vertex fast) first, each group in its original order (deterministic)
    std::vector<int> order;
    for (int pass = 0; pass < 2; ++pass)
      for (int t = 0; t < nt; ++t) {
        const int* v = &v0[4 * t];
        const bool is_slow = slow[v[0]] && slow[v[1]] && slow[v[2]] && slow[v[3]];
        if (is_slow == (pass == 1)) order.push_back(t);
      }
    int nf = 0;
    for (int t = 0; t < nt; ++t) {
      const int* v = &v0[4 * t];
      nf += !(slow[v[0]] && slow[v[1]] && slow[v[2]] && slow[v[3]]);
    }
    for (int k = 0; k < nt; ++k) {
      const int t = order[k];
      for (int i = 0; i < 4; ++i) te.v[4 * k + i] = v0[4 * t + i];
      for (int i = 0; i < 9; ++i) te.g[9 * k + i] = g0[9 * t + i];
      te.vol0[k] = vol00[t];
      te.mu[k] = mu0[t];
    }
    te.fast_count = nf;
    if (nf == nt) return "multirate: no tet element admits the whole tick; every element runs every substep";
    const double slow_limit = estimate_stable_dt(m, TetPass::SlowOnly);
    if (margin * slow_limit >= m.dt) {
      char b[200];
      std::snprintf(b, sizeof b, "multirate: %d of %d tet elements once per tick (slow group's stable step %.3g ms)",
                    nt - nf, nt, slow_limit * 1e3);
      return b;
    }
    // the estimate does not confirm it: the stiffest tenth of the slow particles become fast
    std::vector<std::pair<double, int>> by_limit;
    for (int p = 0; p < n; ++p)
      if (slow[p]) by_limit.emplace_back(limit[p], p);
    std::sort(by_limit.begin(), by_limit.end());
    const size_t drop = std::max<size_t>(1, by_limit.size() / 10);
    for (size_t i = 0; i < drop && i < by_limit.size(); ++i) slow[by_limit[i].second] = 0;
  }
  // give up: every element every substep
  te.v = v0; te.g = g0; te.vol0 = vol00; te.mu = mu0;
  te.fast_count = nt;
  return "multirate: the slow group's estimate never admitted the tick; every element runs every substep";
}

std::shared_ptr<const Model> compile_scenario(const ScenarioSpec& spec, CompileReport* report) {
  const auto t_start = std::chrono::steady_clock::now();
  check_scenario_size(spec);  // refuses before allocating: names the spacing_mm to change
  auto model = std::make_shared<Model>();
  Model& m = *model;
  m.name = spec.name;
  m.source_file = spec.file;
  m.dt = spec.dt;
  m.substeps = spec.substeps;
  m.duration = spec.duration;
  m.gravity = spec.gravity;
  m.redistribution = spec.linear_redistribution ? Redistribution::Linear : Redistribution::Gradient;
  m.max_triplets = spec.max_triplets;
  std::vector<std::string> warnings, notes;

  // particles of every component, contiguous per component
  std::vector<std::vector<int>> nbrs;  // global neighbour lists, filled per component then links
  std::vector<std::vector<std::array<int, 3>>> faces_of(spec.components.size());
  // components that exclude others (fat around organs) are filled after the others
  std::vector<ParticleSet> sets(spec.components.size());
  std::vector<double> excluded_volume(spec.components.size(), 0.0);  // [m^3]
  for (size_t ci = 0; ci < spec.components.size(); ++ci)
    if (spec.components[ci].exclude_inside.empty()) sets[ci] = build_particles(spec.components[ci], spec.file, &warnings);
  for (size_t ci = 0; ci < spec.components.size(); ++ci)
    if (!spec.components[ci].exclude_inside.empty())
      sets[ci] = anatomy::fill_excluding(spec, ci, sets, &excluded_volume[ci]);
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    const ComponentSpec& cs = spec.components[ci];
    ParticleSet set = std::move(sets[ci]);
    if (set.pos.empty())
      throw InputError(spec.file, cs.loc.line, "components." + cs.name, "component has no particles");
    Component comp;
    comp.name = cs.name;
    comp.kind = cs.kind == "rigid" ? ComponentKind::Rigid : cs.kind == "active" ? ComponentKind::Active : ComponentKind::Elastic;
    comp.first_particle = m.particle_count();
    comp.particle_count = static_cast<int>(set.pos.size());
    comp.spacing = cs.spacing;
    comp.volumetric = cs.volumetric;
    comp.fibre_dir = cs.fibre;
    comp.active_force = cs.active_stress * cs.spacing * cs.spacing;
    const int off = comp.first_particle;
    for (size_t p = 0; p < set.pos.size(); ++p) {
      m.rest_pos.push_back(set.pos[p]);
      m.component_of.push_back(static_cast<int>(ci));
      m.on_surface.push_back(set.on_surface[p]);
      std::vector<int> nb;
      for (int q : set.nbrs[p]) nb.push_back(q + off);
      nbrs.push_back(std::move(nb));
    }
    for (auto f : set.faces) faces_of[ci].push_back({f[0] + off, f[1] + off, f[2] + off});
    m.components.push_back(comp);
  }
  const int n = m.particle_count();

  // materials: mass from the component's enclosed volume, stiffness from E and spacing
  m.mass.assign(n, 0.0);
  m.k_e.assign(n, 0.0);
  m.k_c.assign(n, 0.0);
  m.k_f.assign(n, 0.0);
  m.damping.assign(n, 0.0);
  std::vector<StrainParticle> strain(n);  // strain-model material per particle (mu = 0: none)
  bool any_strain = false;
  std::vector<TetParticle> tet(n);  // tet-model material per particle (mu = 0: none)
  bool any_tet = false;
  std::vector<ShellParticle> shell(n);  // shell-model material per particle (mu = 0: none)
  bool any_shell = false;
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    const ComponentSpec& cs = spec.components[ci];
    const MaterialSpec& mat = find_material(spec, cs.material);
    const Component& comp = m.components[ci];
    double volume = 0.0;
    for (const auto& f : faces_of[ci]) volume += m.rest_pos[f[0]].dot(m.rest_pos[f[1]].cross(m.rest_pos[f[2]])) / 6.0;
    if (mat.shell_model && cs.volumetric)
      throw InputError(spec.file, mat.loc.line, "materials." + mat.name + ".model",
                       "model: shell is for membranes, '" + cs.name + "' is volumetric (give it fill: surface)");
    if (!cs.volumetric) {
      // membrane: mass of a wall one spacing thick (paper model) or of the shell's own thickness
      double area = 0.0;
      for (const auto& f : faces_of[ci])
        area += 0.5 * (m.rest_pos[f[1]] - m.rest_pos[f[0]]).cross(m.rest_pos[f[2]] - m.rest_pos[f[0]]).norm();
      volume = area * (mat.shell_model ? *mat.thickness : cs.spacing);
    }
    volume -= excluded_volume[ci];  // the organs inside a fat block are not fat
    if (!(volume > 0.0))
      throw CompileError("component '" + cs.name + "': surface encloses no positive volume (inverted or open)");
    const double pm = mat.density * volume / comp.particle_count;
    StrainParticle sp;
    TetParticle tp;
    ShellParticle shp;
    if (mat.shell_model) {
      const double nu = mat.poisson ? *mat.poisson : mat.incompressible ? kStrainPoissonIncompressible : kStrainPoissonDefault;
      shp.mu = strain_moduli(*mat.young, nu).mu;
      shp.poisson = nu;
      shp.thickness = *mat.thickness;
      any_shell = true;
    }
    if (mat.tet_model) {
      if (!cs.volumetric)
        throw InputError(spec.file, mat.loc.line, "materials." + mat.name + ".model",
                         "model: tet needs volumetric components, '" + cs.name + "' is fill: surface");
      const double nu = mat.poisson ? *mat.poisson : mat.incompressible ? kStrainPoissonIncompressible : kStrainPoissonDefault;
      const StrainModuli sm = strain_moduli(*mat.young, nu);
      tp.mu = sm.mu;
      tp.lambda = sm.lambda;
      any_tet = true;
    }
    if (mat.strain_model) {
      if (!cs.volumetric)
        throw InputError(spec.file, mat.loc.line, "materials." + mat.name + ".model",
                         "model: strain needs volumetric components, '" + cs.name + "' is fill: surface");
      const double nu = mat.poisson ? *mat.poisson : mat.incompressible ? kStrainPoissonIncompressible : kStrainPoissonDefault;
      if (mat.k_s) {  // raw: mu = k_s / h, lambda from the same local Poisson ratio
        sp.mu = *mat.k_s / cs.spacing;
        sp.lambda = 2.0 * sp.mu * nu / (1.0 - 2.0 * nu);
      } else {
        const StrainModuli sm = strain_moduli(*mat.young, nu);
        sp.mu = sm.mu;
        sp.lambda = sm.lambda;
      }
      sp.volume = volume / comp.particle_count;
      any_strain = true;
    }
    const double ke = mat.k_e               ? *mat.k_e
                      : mat.tet_model || mat.shell_model ? 0.0  // the elements carry the whole stiffness
                      : mat.strain_model    ? strain_shape_memory_stiffness(sp.mu, cs.spacing)
                                            : shape_memory_stiffness(*mat.young, cs.spacing);
    if (!mat.k_e && !mat.strain_model && !mat.tet_model && !mat.shell_model && comp.kind != ComponentKind::Rigid && (cs.spacing < kCalibratedSpacingMin || cs.spacing > kCalibratedSpacingMax))
      warnings.push_back("component '" + cs.name + "': spacing " + std::to_string(cs.spacing * 1e3) +
                         " mm is outside the 4-10 mm range where the E -> k_e mapping was calibrated");
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      m.mass[p] = pm;
      m.k_e[p] = ke;
      m.k_c[p] = mat.k_c;
      m.k_f[p] = mat.k_f;
      m.damping[p] = mat.damping;
      strain[p] = sp;
      tet[p] = tp;
      shell[p] = shp;
    }
  }
  for (size_t oi = 0; oi < spec.overrides.size(); ++oi) {
    const OverrideSpec& o = spec.overrides[oi];
    const int ci = m.find_component(o.component);
    const Component& comp = m.components[ci];
    int hits = 0;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p) {
      if (!o.region.contains(m.rest_pos[p])) continue;
      ++hits;
      if (o.young && shell[p].mu > 0.0) {
        shell[p].mu = strain_moduli(*o.young, shell[p].poisson).mu;
      } else if (o.young && tet[p].mu > 0.0) {
        const double nu = tet[p].lambda / (2.0 * (tet[p].lambda + tet[p].mu));
        const StrainModuli sm = strain_moduli(*o.young, nu);
        tet[p].mu = sm.mu;
        tet[p].lambda = sm.lambda;
      } else if (o.young && strain[p].mu > 0.0) {
        // strain model: the same local Poisson ratio, the new modulus
        const double nu = strain[p].lambda / (2.0 * (strain[p].lambda + strain[p].mu));
        const StrainModuli sm = strain_moduli(*o.young, nu);
        strain[p].mu = sm.mu;
        strain[p].lambda = sm.lambda;
        m.k_e[p] = strain_shape_memory_stiffness(sm.mu, comp.spacing);
      } else if (o.young) {
        m.k_e[p] = shape_memory_stiffness(*o.young, comp.spacing);
      }
      if (o.k_e) m.k_e[p] = *o.k_e;
      if (o.k_c) m.k_c[p] = *o.k_c;
      if (o.k_f) m.k_f[p] = *o.k_f;
      if (o.damping) m.damping[p] = *o.damping;
    }
    if (hits == 0)
      throw InputError(spec.file, o.loc.line, "overrides[" + std::to_string(oi) + "].region",
                       "selects no particle of component '" + o.component + "'");
  }

  anatomy::apply_particle_tags(spec, m, faces_of);  // tags: and prostate_zones:

  // rigid components become bodies
  m.inv_mass.assign(n, 0.0);
  m.shape_memory.assign(n, 0);
  m.locked_axes.assign(n, 0);
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    Component& comp = m.components[ci];
    const int b = comp.first_particle, e = b + comp.particle_count;
    if (comp.kind != ComponentKind::Rigid) {
      for (int p = b; p < e; ++p) { m.inv_mass[p] = 1.0 / m.mass[p]; m.shape_memory[p] = 1; }
      continue;
    }
    RigidBody rb;
    rb.component = static_cast<int>(ci);
    rb.kinematic = spec.components[ci].kinematic;
    for (int p = b; p < e; ++p) { rb.mass += m.mass[p]; rb.com_rest += m.mass[p] * m.rest_pos[p]; }
    rb.com_rest /= rb.mass;
    rb.inertia_body.setZero();
    for (int p = b; p < e; ++p) {
      const Vec3 r = m.rest_pos[p] - rb.com_rest;
      rb.particles.push_back(p);
      rb.local.push_back(r);
      rb.inertia_body += m.mass[p] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
      m.locked_axes[p] = 7;
    }
    comp.rigid_body = static_cast<int>(m.rigid_bodies.size());
    m.rigid_bodies.push_back(std::move(rb));
  }

  // links across components (paper §3.1, Fig. 3)
  for (size_t li = 0; li < spec.links.size(); ++li) {
    const LinkSpec& l = spec.links[li];
    const Component& A = m.components[m.find_component(l.a)];
    const Component& B = m.components[m.find_component(l.b)];
    const bool ra = A.kind == ComponentKind::Rigid, rb = B.kind == ComponentKind::Rigid;
    if (ra && rb)
      throw InputError(spec.file, l.loc.line, "links[" + std::to_string(li) + "]",
                       "two rigid components are linked through an elastic component, not directly");
    int made = 0;
    if (ra || rb) {
      // rigid-elastic: elastic border particles doubled onto the body
      const Component& R = ra ? A : B;
      const Component& E = ra ? B : A;
      std::vector<Vec3> rpts(m.rest_pos.begin() + R.first_particle, m.rest_pos.begin() + R.first_particle + R.particle_count);
      const SpatialGrid grid(rpts, l.distance);
      const RigidBody& body = m.rigid_bodies[R.rigid_body];
      for (int p = E.first_particle; p < E.first_particle + E.particle_count; ++p) {
        bool near = false;
        grid.for_each_within(m.rest_pos[p], l.distance, [&](int, double) { near = true; });
        if (!near || m.inv_mass[p] == 0.0) continue;
        m.attachments.push_back(RigidAttachment{p, R.rigid_body, m.rest_pos[p] - body.com_rest});
        m.inv_mass[p] = 0.0;
        m.locked_axes[p] = 7;
        ++made;
      }
    } else {
      // elastic-elastic: border particles get their nearest neighbours in the other component
      auto connect = [&](const Component& from, const Component& to) {
        std::vector<Vec3> tpts(m.rest_pos.begin() + to.first_particle, m.rest_pos.begin() + to.first_particle + to.particle_count);
        const SpatialGrid grid(tpts, l.distance);
        for (int p = from.first_particle; p < from.first_particle + from.particle_count; ++p) {
          std::vector<std::pair<double, int>> cand;
          grid.for_each_within(m.rest_pos[p], l.distance, [&](int q, double d) { cand.emplace_back(d, q + to.first_particle); });
          std::sort(cand.begin(), cand.end());
          for (size_t c = 0; c < cand.size() && c < 3; ++c) {
            if (nbrs[p].size() >= static_cast<size_t>(kMaxNeighbours)) break;
            nbrs[p].push_back(cand[c].second);
            ++made;
          }
        }
      };
      connect(A, B);
      connect(B, A);
    }
    if (made == 0)
      throw InputError(spec.file, l.loc.line, "links[" + std::to_string(li) + "].distance_mm",
                       "no particles of '" + l.a + "' and '" + l.b + "' are that close: nothing linked");
  }

  // neighbourhoods to CSR; rigid particles carry no shape memory
  m.nbr_start.assign(n + 1, 0);
  for (int p = 0; p < n; ++p) {
    m.nbr_start[p] = static_cast<int>(m.nbr.size());
    if (m.shape_memory[p]) m.nbr.insert(m.nbr.end(), nbrs[p].begin(), nbrs[p].end());
  }
  m.nbr_start[n] = static_cast<int>(m.nbr.size());

  // constraints and applied forces
  for (size_t ki = 0; ki < spec.constraints.size(); ++ki) {
    const ConstraintSpec& c = spec.constraints[ki];
    const std::string key = "constraints[" + std::to_string(ki) + "]";
    std::vector<int> sel;
    for (int p = 0; p < n; ++p) {
      if (!c.component.empty() && m.components[m.component_of[p]].name != c.component) continue;
      if (m.components[m.component_of[p]].kind == ComponentKind::Rigid) continue;
      if (c.kind == ConstraintSpec::HalfSpace || c.region.contains(m.rest_pos[p])) sel.push_back(p);
    }
    if (sel.empty()) throw InputError(spec.file, c.loc.line, key + ".region", "selects no particle");
    switch (c.kind) {
      case ConstraintSpec::Fix:
        for (int p : sel) { m.fixed.push_back({p, c.axes}); m.locked_axes[p] |= c.axes; }
        break;
      case ConstraintSpec::Displace:
        m.imposed.push_back(ImposedDisplacement{sel, c.by, c.axes, c.t0, c.t1});
        for (int p : sel) m.locked_axes[p] |= c.axes;
        break;
      case ConstraintSpec::HalfSpace: {
        for (int p : sel)
          if ((m.rest_pos[p] - c.region.point).dot(c.region.normal) < -1e-9)
            throw InputError(spec.file, c.loc.line, key + ".point_mm",
                             "particle " + std::to_string(p) + " starts outside the allowed half-space");
        m.half_spaces.push_back(HalfSpace{sel, c.region.point, c.region.normal});
        break;
      }
      case ConstraintSpec::Force: m.applied_forces.push_back(AppliedForce{sel, c.by, c.t0, c.t1}); break;
    }
  }

  compute_discrete_coordinates(m);

  // surfaces: one per component; volume-constrained when the material is incompressible
  for (size_t ci = 0; ci < spec.components.size(); ++ci) {
    const MaterialSpec& mat = find_material(spec, spec.components[ci].material);
    Surface s;
    s.component = static_cast<int>(ci);
    s.faces = faces_of[ci];
    std::vector<int> verts;
    for (const auto& f : s.faces) verts.insert(verts.end(), f.begin(), f.end());
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    s.vertices = verts;
    for (const auto& f : s.faces) {
      const Vec3 cr = (m.rest_pos[f[1]] - m.rest_pos[f[0]]).cross(m.rest_pos[f[2]] - m.rest_pos[f[0]]);
      if (!(cr.norm() > 0.0))
        throw CompileError("component '" + spec.components[ci].name + "': zero-area surface face (" +
                           std::to_string(f[0]) + ", " + std::to_string(f[1]) + ", " + std::to_string(f[2]) + ")");
    }
    s.rest_volume = surface_volume(s, m.rest_pos);
    s.volume_constrained = mat.incompressible && m.components[ci].kind != ComponentKind::Rigid;
    m.components[ci].surface = static_cast<int>(m.surfaces.size());
    m.surfaces.push_back(std::move(s));
  }

  if (any_strain)  // after the surfaces: the clusters' consistency condition uses them
    for (auto& w : build_strain_clusters(m, strain)) warnings.push_back(w);
  if (any_tet) {  // after the surfaces: elements outside a component's surface are dropped
    std::vector<std::vector<int>> excluded(m.components.size());
    for (size_t ci = 0; ci < spec.components.size(); ++ci)
      for (const std::string& other : spec.components[ci].exclude_inside) {
        const int oc = m.find_component(other);
        if (oc >= 0 && m.components[oc].surface >= 0) excluded[ci].push_back(m.components[oc].surface);
      }
    // links between two tet components, or a tet component and a shell (the tissue around a wall
    // reaches it through elements spanning the gap, of the tet side's material)
    std::vector<TetLink> tet_links;
    for (const LinkSpec& l : spec.links) {
      const int a = m.find_component(l.a), b = m.find_component(l.b);
      if (a < 0 || b < 0) continue;
      const int pa = m.components[a].first_particle, pb = m.components[b].first_particle;
      const bool ta = tet[pa].mu > 0.0, tb = tet[pb].mu > 0.0;
      if ((ta && tb) || (ta && shell[pb].mu > 0.0) || (tb && shell[pa].mu > 0.0)) tet_links.push_back(TetLink{a, b, l.distance});
    }
    // dropping slivers and hull elements is by design (tet_elements.cpp): a note, not a warning
    for (auto& w : build_tet_elements(m, tet, excluded, tet_links))
      (w.find("left out") != std::string::npos ? notes : warnings).push_back(w);
    // a particle no element reaches keeps the lattice shape-matching stiffness mu h of the
    // paper's term, so it stays attached to its neighbours
    for (int p = 0; p < n; ++p)
      if (tet[p].mu > 0.0 && m.tets.node_slot[p] < 0 && !m.k_e[p]) m.k_e[p] = tet[p].mu * m.components[m.component_of[p]].spacing;
    // an element node with k_e = 0 carries no shape-memory force: drop its triplets so the
    // shape-memory stage does not evaluate attractors that are multiplied by zero (they cost
    // about half of a tet scene's substep). The neighbour graph stays: the needle's zone search
    // walks it.
    bool dropped = false;
    for (int p = 0; p < n; ++p)
      if (m.shape_memory[p] && m.tets.node_slot[p] >= 0 && !(m.k_e[p] > 0.0)) { m.shape_memory[p] = 0; dropped = true; }
    if (dropped) compute_discrete_coordinates(m);
  }
  if (any_shell) {  // after the surfaces: the shells are their faces
    build_shell_elements(m, shell);
    // the elements carry the wall's stiffness (k_e = 0): no attractor to evaluate
    bool dropped = false;
    for (int p = 0; p < n; ++p)
      if (m.shape_memory[p] && shell[p].mu > 0.0 && !(m.k_e[p] > 0.0)) { m.shape_memory[p] = 0; dropped = true; }
    if (dropped) compute_discrete_coordinates(m);
  }
  m.any_shape_memory = false;
  for (int p = 0; p < n; ++p) m.any_shape_memory |= (m.shape_memory[p] && m.k_e[p] > 0.0);

  // active fibres: neighbour pairs whose rest direction is within 30 degrees of the fibre
  for (size_t ci = 0; ci < m.components.size(); ++ci) {
    const Component& comp = m.components[ci];
    if (comp.kind != ComponentKind::Active) continue;
    for (int p = comp.first_particle; p < comp.first_particle + comp.particle_count; ++p)
      for (int a = m.nbr_start[p]; a < m.nbr_start[p + 1]; ++a) {
        const int q = m.nbr[a];
        if (q <= p || m.component_of[q] != static_cast<int>(ci)) continue;
        const Vec3 d = (m.rest_pos[q] - m.rest_pos[p]).normalized();
        if (std::abs(d.dot(comp.fibre_dir)) > std::cos(30.0 * 3.14159265358979 / 180.0))
          m.fibre_pairs.push_back(FibrePair{p, q, static_cast<int>(ci)});
      }
  }

  // stability: raise substeps so each substep is at most 90% of the estimated limit, or (with
  // solver.mass_scaling) add inertia to the particles that set the limit
  if (spec.multirate) notes.push_back(partition_tet_rates(m, 0.9));
  // with multi-rate the substep is set by the fast group (the held slow force is a constant
  // within a tick); the slow group was checked against the tick above
  m.stable_dt_estimate = estimate_stable_dt(m, m.tets.multirate() ? TetPass::FastOnly : TetPass::All);
  if (spec.mass_scaling) scale_inertia_to_substep(m, 0.9);
  const double h = m.dt / m.substeps;
  if (h > 0.9 * m.stable_dt_estimate) {
    // In double first: a stiffness like young_kpa 1e9 gives a stable step so small that the count
    // overflows an int (it used to wrap to -2147483648 and the run "succeeded" with 0 steps).
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
  m.compile_warnings = warnings;
  if (report) {
    report->warnings = warnings;
    report->notes = notes;
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  }
  return model;
}

}  // namespace ps
