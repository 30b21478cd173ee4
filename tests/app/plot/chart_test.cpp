// Tests for app/plot/chart.cpp and canvas.cpp: tick choice, labels, and that what is drawn lands
// where the axes say (a point's pixel holds its series colour; text leaves ink).
#include "app/plot/chart.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ps::plot {
namespace {

bool is_color(Rgb p, Rgb c, int tol = 40) {
  return std::abs(p.r - c.r) <= tol && std::abs(p.g - c.g) <= tol && std::abs(p.b - c.b) <= tol;
}

int count_color(const Canvas& cv, Rgb c, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += is_color(cv.at(x, y), c, 10);
  return n;
}

TEST(PlotTicks, LinearTicksAreNiceAndCoverRange) {
  const auto t = linear_ticks(0.0, 1.0, 6);
  ASSERT_EQ(t.size(), 6u);
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_NEAR(t[1], 0.2, 1e-12);
  EXPECT_NEAR(t.back(), 1.0, 1e-12);
  const auto u = linear_ticks(-3.7, 12.1, 6);
  for (double v : u) {
    EXPECT_GE(v, -3.7);
    EXPECT_LE(v, 12.1);
  }
  EXPECT_NEAR(u[1] - u[0], 2.0, 1e-12);  // 15.8 / 5 = 3.16 -> the nice step 2
}

TEST(PlotTicks, LogTicksAreDecadesAndSubdivideShortRanges) {
  const auto t = log_ticks(1e-3, 1e2);
  ASSERT_EQ(t.size(), 6u);
  EXPECT_NEAR(t.front(), 1e-3, 1e-15);
  EXPECT_NEAR(t.back(), 100, 1e-9);
  const auto s = log_ticks(1.0, 100.0);  // two decades: 1 2 5 10 20 50 100
  EXPECT_EQ(s.size(), 7u);
}

TEST(PlotTicks, LabelsAreShort) {
  EXPECT_EQ(tick_label(0.2, 0.2, false), "0.2");
  EXPECT_EQ(tick_label(15, 5, false), "15");
  EXPECT_EQ(tick_label(1e-5, 0, true), "1e-5");
  EXPECT_EQ(tick_label(2e6, 0, true), "2e6");
  EXPECT_EQ(tick_label(0.01, 0, true), "0.01");
  EXPECT_EQ(tick_label(0, 1, false), "0");
}

TEST(PlotCanvas, TextLeavesInkAndOddBytesAreSafe) {
  Canvas cv(200, 40);
  cv.text(2, 2, "Abc 1.5 \xc2\xb5s\x01", {0, 0, 0}, 2);
  EXPECT_GT(count_color(cv, {0, 0, 0}, 0, 0, 200, 40), 50);
  EXPECT_GT(Canvas::text_width("Abc", 2), Canvas::text_width("A", 2));
}

TEST(PlotChart, PointsLandWhereTheAxesSay) {
  Chart c;
  c.title = "test";
  c.x = {"x [mm]", false, 0, 10};
  c.y = {"y [N]", false, 0, 10};
  Series s;
  s.label = "data";
  s.x = {5};
  s.y = {5};
  s.line = false;
  s.marker = Marker::Square;
  s.marker_size = 14;
  s.color = {214, 39, 40};
  c.series.push_back(s);
  c.legend = LegendPos::None;
  const Canvas cv = render(c, 640, 480);
  // Find the red blob's centre; with axes 0..10 the point (5, 5) is the plot area's centre, so the
  // blob must be right of and above the canvas centre only by the margins' asymmetry (< 60 px).
  double sx = 0, sy = 0;
  int n = 0;
  for (int y = 0; y < cv.height(); ++y)
    for (int x = 0; x < cv.width(); ++x)
      if (is_color(cv.at(x, y), s.color, 10)) { sx += x; sy += y; ++n; }
  ASSERT_GT(n, 50);
  EXPECT_NEAR(sx / n, 320, 60);
  EXPECT_NEAR(sy / n, 240, 40);
}

// LegendPos::Best (the default) puts the legend in the corner where it hides the least data. With
// points in both top corners and a line along the bottom right, only the bottom left is clear.
TEST(PlotChart, TheBestLegendCornerHidesNoData) {
  Chart c;
  c.x = {"x", false, 0, 10};
  c.y = {"y", false, 0, 10};
  Series pts;
  pts.label = "points in the top corners";
  pts.x = {9.5, 9.0, 0.5, 1.0};
  pts.y = {9.5, 9.0, 9.5, 9.0};
  pts.line = false;
  pts.marker = Marker::Square;
  pts.color = {214, 39, 40};
  Series line;
  line.label = "a line along the bottom right";
  line.x = {5, 10};
  line.y = {0.5, 0.5};
  line.color = {31, 119, 180};
  c.series = {pts, line};
  const Canvas best = render(c, 640, 480);
  int hidden = 0;  // red pixels with the best corner: every marker shows
  for (int y = 0; y < best.height(); ++y)
    for (int x = 0; x < best.width(); ++x) hidden += is_color(best.at(x, y), pts.color, 10);
  c.legend = LegendPos::BottomLeft;
  const Canvas bottom_left = render(c, 640, 480);
  EXPECT_TRUE(best.pixels() == bottom_left.pixels()) << "the legend went elsewhere than the one clear corner";
  c.legend = LegendPos::TopRight;  // the fixed corner: over two of the points
  const Canvas top_right = render(c, 640, 480);
  int shown = 0;  // red pixels with the legend top right
  for (int y = 0; y < top_right.height(); ++y)
    for (int x = 0; x < top_right.width(); ++x) shown += is_color(top_right.at(x, y), pts.color, 10);
  EXPECT_LT(shown, hidden);  // the fixed corner hid some of the markers
}

TEST(PlotChart, LogAxisSkipsNonPositiveAndNonFinitePoints) {
  Chart c;
  c.x.log = true;
  c.y.log = true;
  Series s;
  s.x = {1e-3, 0.0, 1e-1, NAN, 10};
  s.y = {1, 2, -1, 4, 100};
  s.marker = Marker::Circle;
  c.series.push_back(s);
  const Canvas cv = render(c, 400, 300);  // must not crash or draw garbage
  EXPECT_GT(count_color(cv, s.color, 0, 0, 400, 300), 20);
}

TEST(PlotChart, EmptyChartStillHasAFrame) {
  Chart c;
  const Canvas cv = render(c, 300, 200);
  EXPECT_GT(count_color(cv, {60, 60, 60}, 0, 0, 300, 200), 100);
}

}  // namespace
}  // namespace ps::plot
