#include "app/gui/plot_axes.h"

#include <cmath>
#include <initializer_list>

namespace ps::gui {

ForceAxis force_axis(float fmin, float fmax) {
  ForceAxis a;
  for (float step : {0.25f, 0.5f, 1.0f, 2.0f, 2.5f, 5.0f, 10.0f, 20.0f, 25.0f, 50.0f}) {
    a.step = step;
    a.lo = std::floor(fmin / step) * step;
    if (a.hi() >= fmax) break;
  }
  return a;
}

float depth_axis_max(float dmax) { return dmax <= 10.0f ? 10.0f : std::ceil(dmax / 20.0f) * 20.0f; }

}  // namespace ps::gui
