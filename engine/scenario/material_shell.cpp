// model: shell, membranes on a component's surface (fill: surface): co-rotational constant-strain
// triangles and dihedral hinges (docs/model.md "Shell model"; engine/model/shell_elements.h,
// engine/step/shell_elastic.cpp).
#include <string>

#include "engine/model/discrete_coordinates.h"
#include "engine/model/shell_elements.h"
#include "engine/scenario/material_models.h"
#include "engine/scenario/model_hash.h"
#include "engine/util/error.h"

namespace ps {

namespace {

void shell_check(const ComponentMaterialInput& in) {
  if (in.cs.volumetric)
    throw InputError(in.spec.file, in.mat.loc.line, "materials." + in.mat.name + ".model",
                     "model: shell is for membranes, '" + in.cs.name + "' is volumetric (give it fill: surface)");
}

// k_e = 0: the elements carry the whole stiffness
void shell_moduli(const ComponentMaterialInput& in, ParticleMaterial& out, std::vector<std::string>&) {
  const double nu = local_poisson(in.mat);
  out.shell.mu = strain_moduli(*in.mat.young, nu).mu;
  out.shell.poisson = nu;
  out.shell.thickness = *in.mat.thickness;
}

void shell_override_young(double young_pa, double, int p, Model&, CompileWork& work) {
  work.shell[p].mu = strain_moduli(young_pa, work.shell[p].poisson).mu;
}

// after the surfaces: the shells are their faces
void shell_build(const ScenarioSpec&, Model& m, CompileWork& work) {
  build_shell_elements(m, work.shell);
  // the elements carry the wall's stiffness (k_e = 0): no attractor to evaluate
  bool dropped = false;
  for (int p = 0, n = m.particle_count(); p < n; ++p)
    if (m.shape_memory[p] && work.shell[p].mu > 0.0 && !(m.k_e[p] > 0.0)) { m.shape_memory[p] = 0; dropped = true; }
  if (dropped) compute_discrete_coordinates(m);
}

bool shell_present(const Model& m) { return m.shells.triangle_count() > 0; }

void shell_add_forces(const Model& m, State& s, TetPass pass) {
  if (pass != TetPass::SlowOnly && m.shells.triangle_count() > 0) add_shell_elastic_forces(m, s);
}

void shell_add_stiffness(const Model& m, bool, ProxyForm, std::vector<double>& d) {
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
}

// the membrane triangles and hinges with their rest data and moduli
void shell_hash(const Model& m, ModelHasher& h) {
  h.vec(m.shells.tri);
  h.vec(m.shells.bm);
  h.vec(m.shells.area_t);
  h.vec(m.shells.mu);
  h.vec(m.shells.lambda);
  h.vec(m.shells.hinge);
  h.vec(m.shells.theta0);
  h.vec(m.shells.k_hinge);
}

}  // namespace

const MaterialModelDesc kShellMaterial{MaterialModel::Shell, "shell", Stage::ShellElastic, shell_check, shell_moduli,
                                       shell_override_young, shell_build, shell_present, shell_add_forces, shell_add_stiffness,
                                       shell_elastic_energy, shell_hash};

}  // namespace ps
