// Tests for app/gui/plot_axes.cpp: the trainee window's force plot keeps every sample inside its
// frame, negative forces included (a withdrawal's friction drew its curve out of the plot, over
// the ultrasound panel, before), with round steps and 0 on a grid line.
#include "app/gui/plot_axes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ps::gui {
namespace {

TEST(PlotAxes, ForceAxisCoversTheSamplesInFourRoundStepsWithZeroOnTheGrid) {
  struct Case {
    float fmin, fmax, lo, step;
  };
  const Case cases[] = {
      {0.0f, 1.0f, 0.0f, 0.25f},    // nothing yet: 0, 0.25, ... 1 N
      {0.0f, 2.21f, 0.0f, 1.0f},    // biopsy insertion: 0..4 N
      {-1.23f, 2.21f, -2.0f, 2.0f}, // and its withdrawal: -2..6 N (steps of 1 end at 2 N)
      {-0.9f, 2.9f, -1.0f, 1.0f},   // -1..3 N
      {0.0f, 9.0f, 0.0f, 2.5f},     // brachytherapy's perineum: 0..10 N
      {-30.0f, 45.0f, -50.0f, 25.0f},
      {0.0f, 400.0f, 0.0f, 50.0f},  // past the largest step: its range, the caller clips
  };
  for (const Case& c : cases) {
    const ForceAxis a = force_axis(c.fmin, c.fmax);
    EXPECT_FLOAT_EQ(a.lo, c.lo) << c.fmin << " .. " << c.fmax;
    EXPECT_FLOAT_EQ(a.step, c.step) << c.fmin << " .. " << c.fmax;
    EXPECT_LE(a.lo, c.fmin);
    if (c.fmax <= 200.0f) EXPECT_GE(a.hi(), c.fmax);
    const float k = -a.lo / a.step;  // 0 is lo + k steps: a whole number
    EXPECT_FLOAT_EQ(k, std::round(k));
  }
}

TEST(PlotAxes, DepthAxisEndsAtTenOrAMultipleOfTwenty) {
  EXPECT_FLOAT_EQ(depth_axis_max(0.0f), 10.0f);
  EXPECT_FLOAT_EQ(depth_axis_max(10.0f), 10.0f);
  EXPECT_FLOAT_EQ(depth_axis_max(10.5f), 20.0f);
  EXPECT_FLOAT_EQ(depth_axis_max(21.4f), 40.0f);
  EXPECT_FLOAT_EQ(depth_axis_max(75.0f), 80.0f);
}

}  // namespace
}  // namespace ps::gui
