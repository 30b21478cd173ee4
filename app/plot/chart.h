// A 2D chart (line and scatter series, linear or log axes, ticks with numeric labels, title,
// axis labels, legend) rasterized into a Canvas. Used by `prostatesim bench` for the run time
// against error chart and by anyone who needs a figure; write the result with
//   ps::write_png_atomic(path, c.width(), c.height(), 3, c.pixels().data());
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "app/plot/canvas.h"

namespace ps::plot {

struct Series {
  std::string label;           // shown in the legend; empty = not listed
  std::vector<double> x, y;    // same length; non-finite points (and <= 0 on a log axis) skipped
  Rgb color{31, 119, 180};
  bool line = true;            // connect the points in the given order
  bool dashed = false;
  double line_width = 2.0;     // [px]
  Marker marker = Marker::None;
  double marker_size = 9.0;    // [px]
};

struct Axis {
  std::string label;
  bool log = false;            // base-10 logarithmic
  double min = NAN, max = NAN; // NaN: fit the data
};

// Best: the corner whose legend box would cover the fewest of the data (markers, and points along
// the lines), the top right on a tie.
enum class LegendPos { TopRight, TopLeft, BottomRight, BottomLeft, None, Best };

struct Chart {
  std::string title;
  Axis x, y;
  std::vector<Series> series;
  LegendPos legend = LegendPos::Best;
  bool grid = true;
};

// Renders the chart at width x height pixels (text scale grows with the size).
Canvas render(const Chart& chart, int width = 960, int height = 640);

// Colour i of a ten-colour palette that stays distinguishable in print.
Rgb palette(int i);

// Tick positions: "nice" steps (1, 2, 5 x 10^k) covering [lo, hi] with about `target` ticks.
std::vector<double> linear_ticks(double lo, double hi, int target = 6);
// Decades (and 2, 5 between them when the range spans fewer than four decades).
std::vector<double> log_ticks(double lo, double hi);
// A short label for tick value v on an axis whose ticks are `step` apart (linear) or log.
std::string tick_label(double v, double step, bool log);

}  // namespace ps::plot
