// Turns a ScenarioSpec into an immutable Model: particles for every component, neighbourhoods
// (including links across components), discrete deformation coordinates, materials, constraints,
// surfaces with rest volumes, rigid bodies, and the largest stable time step.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "engine/model/model.h"
#include "engine/spec/scenario_spec.h"
#include "engine/step/stages.h"

namespace ps {

struct CompileReport {
  std::vector<std::string> warnings;   // e.g. substeps raised for stability
  std::vector<std::string> notes;      // information, not a fault: elements the tet model left out
  double seconds = 0.0;                // wall time of the compile (not physics)
};

// Throws InputError (bad spec: names file:line and key) or CompileError (degenerate geometry:
// names the particle or face).
std::shared_ptr<const Model> compile_scenario(const ScenarioSpec& spec, CompileReport* report = nullptr);

// Largest stable step of the explicit scheme for the linearisation at rest:
// dt = 2 / sqrt(lambda_max(M^-1 K)), lambda_max by power iteration on finite differences of the
// elastic forces, lowered to (2 / omega)(sqrt(1 + zeta^2) - zeta), zeta = beta omega / 2, where the
// model has stiffness damping beta (Model::stiffness_damping; the mass-proportional damping is
// implicit and sets no limit). [s]
// `pass` selects the tet elements (multi-rate: the fast group with the other force stages, or the
// slow group alone).
double estimate_stable_dt(const Model& model, TetPass pass = TetPass::All);
// Per-particle stiffness proxy d_p [N/m] (omega_p^2 = d_p / m_p of a particle alone), term by term
// (attractors, strain clusters, tet shear and nodal pressure, shell membranes and hinges); it picks
// the particles that multi-rate and mass scaling act on, and the power-iteration estimate confirms.
// fast_only: the tet elements of the multi-rate fast group only (compile_time_step.cpp).
// Diagonal: the diagonal of the elastic stiffness at rest (for the tet model between the largest
// eigenvalue and the trace of the particle's own 3x3 block); sizes inertia (mass scaling,
// multi-rate inertia). ElementBound: the nodal pressure counted per element, V0 kappa |g_i|^2, ~8x
// the diagonal in nearly incompressible fat; gates the multi-rate slow group (the diagonal as the
// gate lets fat next to the rectal wall into it at a 1 ms tick, and the impulse resonance blows the
// template plan up at 0.59 s: docs/performance.md "What sets the limits").
enum class ProxyForm { Diagonal, ElementBound };
std::vector<double> stiffness_proxy(const Model& model, bool fast_only = false, ProxyForm form = ProxyForm::Diagonal);
// solver.multirate: orders the tet elements fast first and sets TetElements::fast_count; an
// element is slow when its four particles' own stable steps admit the whole tick dt / margin and
// the slow group's estimate (power iteration) confirms it. Returns a line for the compile report.
std::string partition_tet_rates(Model& model, double margin);
// solver.multirate_inertia: the same partition at a tick the soft bulk's own step falls short of,
// with up to max_factor times a particle's inertial mass where that lets its elements join the
// slow group (never on shell vertices or implicit-pressure nodes; taken back where the particle
// ends in no slow element). Appends its lines to notes; false, and the model unchanged, when no
// amplification admits the tick (compile_time_step.cpp).
bool partition_tet_rates_with_inertia(Model& model, double margin, double max_factor, std::vector<std::string>& notes);
// solver.mass_scaling: inertial mass on the particles that set the stable substep, until the
// model's substep dt/substeps is at most `margin` of the estimate (compile_time_step.cpp); updates
// inv_mass, damping, stable_dt_estimate, added_inertia, largest_inertia_factor.
void scale_inertia_to_substep(Model& model, double margin);

}  // namespace ps
