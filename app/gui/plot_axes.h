// Axis ranges of the trainee window's force-versus-depth plot (trainee_window.cpp force_plot):
// chosen here, without ImGui, so that they are tested (tests/gui/plot_axes_test.cpp).
#pragma once

namespace ps::gui {

// Force axis [N] of four equal steps of a round size (0.25, 0.5, 1, 2, 2.5, 5, 10, 20, 25 or 50 N) from a
// multiple of the step, so that 0 is a grid line whenever it is in range, covering [fmin, fmax]
// (fmin <= 0 <= fmax; a withdrawal's friction makes the force negative); the smallest such step.
// Past 200 N of range: steps of 50 N from the multiple below fmin (the coupling clamps at 50 N).
struct ForceAxis {
  float lo = 0.0f, step = 0.25f;  // [N]
  float hi() const { return lo + 4 * step; }
};
ForceAxis force_axis(float fmin, float fmax);

// Depth axis [mm]: 0 to 10 mm, or to the next multiple of 20 mm (quarters: 5, 10, 15, 20 or 10, 20, ...).
float depth_axis_max(float dmax);

}  // namespace ps::gui
