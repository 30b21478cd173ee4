// Local-load validation cases (issue 9): `punch_halfspace` (rigid flat circular punch) and
// `sphere_indentation` (rigid sphere) on a 120 x 120 x 60 mm block (the whole block; the FEM
// used its quarter symmetry), against Boussinesq / Hertz and against a CalculiX field
// (docs/reference/indent_fem.py). The full-field
// error is the RMS and the max of |u_sim - u_fem| over the free particles (every particle whose
// z is not prescribed: the bonded base and the punch face are left out), relative to the largest
// FEM displacement.
#pragma once
#include <string>
#include <vector>

#include "app/checks/validation.h"

namespace ps::app {

struct IndentationAnswer {
  double spacing_mm = 0.0;
  int particles = 0;
  double field_rms = 0.0, field_max = 0.0;  // relative to max |u_fem| [-]
  double profile_rms = 0.0;                  // punch: surface u_z vs Boussinesq, RMS / d [-]
  double fem_profile_rms = 0.0;              // the same for the FEM's own top nodes [-]
  double force1 = 0.0, force2 = 0.0;         // sphere: force on the indenter at depth 1, 2 [N]
  double stable_dt = 0.0;                    // compile's stable substep estimate [s]
  double substep_s = 0.0;                    // substep used [s]
  long long substeps = 0;                    // substeps run
};

// Runs one case ("punch_halfspace" or "sphere_indentation") at a particle spacing [mm] with
// every material's model replaced by `model` ("" keeps the scenario's: paper, strain or tet).
IndentationAnswer run_indentation(const std::string& source_dir, const std::string& name, double spacing_mm,
                                  const std::string& model);

// `prostatesim validate --model M`: the model the indentation cases run (default: the scenario's)
void set_indentation_model(const std::string& model);
// `prostatesim validate --spacings-mm ...`: the particle spacings they run (default 10 and 5;
// multiples of 5 mm, the FEM field's grid)
void set_indentation_spacings(const std::vector<double>& spacings_mm);

std::vector<ValidationCase> indentation_validation_cases();

}  // namespace ps::app
