// Implicit nodal pressure of the tet model (Model::tet_pressure, docs/model.md "Implicit
// pressure"): the compile-time factor and the triangular solves the step uses.
#pragma once
#include <string>

#include "engine/model/model.h"

namespace ps {

// Fills m.tet_pressure for the tet nodes flagged implicit (TetElements::node_implicit): the rows,
// the elements and particles they touch, and the LDL^T factor of J W J^T + alpha / h^2 at rest
// for the substep h = m.dt / m.substeps and the final inertial masses (call after the time-step
// stage: mass scaling changes W). Returns a note for the compile report (empty: nothing implicit).
// Throws CompileError when the factorisation fails (it cannot for a positive compliance, so that
// names a broken model).
std::string build_tet_pressure(Model& m, int iterations);

// Solves (J W J^T + alpha / h^2) y = b with the stored factor: b [k] is overwritten with y;
// work [k] is scratch. No allocation.
void solve_tet_pressure(const TetPressure& tp, double* b, double* work);

}  // namespace ps
