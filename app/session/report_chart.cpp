#include "app/session/report_chart.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "app/plot/chart.h"
#include "engine/metrics/class_report.h"
#include "engine/metrics/score.h"

namespace ps::app {

namespace {

constexpr int kPanelW = 800, kPanelH = 560;

// Histogram of `v` (non-finite values skipped) over bins of `width` from `lo` as a step outline.
plot::Series histogram(const std::vector<double>& v, double lo, double width, int bins, const std::string& label, plot::Rgb color,
                       double& peak) {
  std::vector<int> count(static_cast<size_t>(bins), 0);
  for (double x : v) {
    if (!std::isfinite(x)) continue;
    const int b = std::clamp(static_cast<int>(std::floor((x - lo) / width)), 0, bins - 1);
    ++count[b];
  }
  plot::Series s;
  s.label = label;
  s.color = color;
  s.line_width = 3.0;
  double y_prev = 0.0;
  for (int b = 0; b < bins; ++b) {
    const double x0 = lo + b * width, x1 = x0 + width, y = count[b];
    s.x.insert(s.x.end(), {x0, x0, x1});
    s.y.insert(s.y.end(), {y_prev, y, y});
    y_prev = y;
    peak = std::max(peak, y);
  }
  s.x.push_back(lo + bins * width);
  s.y.push_back(0.0);
  return s;
}

plot::Series vertical(double x, double y0, double y1, const std::string& label, plot::Rgb c) {
  plot::Series s;
  s.label = label;
  s.x = {x, x};
  s.y = {y0, y1};
  s.color = c;
  s.dashed = true;
  return s;
}

plot::Series horizontal(double y, double x0, double x1, const std::string& label, plot::Rgb c) {
  plot::Series s = vertical(0, 0, 0, label, c);
  s.x = {x0, x1};
  s.y = {y, y};
  return s;
}

void blit(RgbImage& img, const plot::Canvas& c, int x0, int y0) {
  for (int y = 0; y < c.height(); ++y)
    std::copy_n(c.pixels().begin() + static_cast<long>(y) * c.width() * 3, c.width() * 3,
                img.pixels.begin() + (static_cast<long>(y0 + y) * img.width + x0) * 3);
}

}  // namespace

RgbImage render_report_chart(const std::vector<MetricsRow>& rows) {
  const plot::Rgb red{200, 40, 40}, green{40, 150, 60};
  std::vector<double> scores, errors;
  double max_error = 10.0;
  for (const MetricsRow& r : rows) {
    scores.push_back(r.score);
    errors.push_back(r.mean_error_mm);
    if (std::isfinite(r.mean_error_mm)) max_error = std::max(max_error, r.mean_error_mm);
  }
  const double err_hi = std::ceil(max_error + 1.0);
  const double robot = 1e3 * kHanRobotError, freehand = 1e3 * kHanFreehandError;

  plot::Chart score_hist;
  score_hist.title = "Score distribution (" + std::to_string(rows.size()) + " sessions)";
  score_hist.x = {"score (0-100)", false, 0.0, 100.0};
  double peak = 0.0;
  score_hist.series.push_back(histogram(scores, 0.0, 10.0, 10, "sessions", plot::palette(0), peak));
  score_hist.y = {"sessions", false, 0.0, std::max(1.0, peak * 1.15)};
  score_hist.legend = plot::LegendPos::TopLeft;

  plot::Chart err_hist;
  err_hist.title = "Mean targeting error per session";
  err_hist.x = {"mean targeting error [mm]", false, 0.0, err_hi};
  peak = 0.0;
  err_hist.series.push_back(histogram(errors, 0.0, 1.0, static_cast<int>(err_hi), "sessions", plot::palette(0), peak));
  const double top = std::max(1.0, peak * 1.15);
  err_hist.y = {"sessions", false, 0.0, top};
  err_hist.series.push_back(vertical(robot, 0.0, top, "robot 1.0 mm (Han 2012)", green));
  err_hist.series.push_back(vertical(freehand, 0.0, top, "freehand 9.0 mm (Han 2012)", red));

  plot::Chart score_curve, err_curve;
  score_curve.title = "Learning curve: score";
  err_curve.title = "Learning curve: mean targeting error";
  size_t most = 1;
  const auto by = sessions_by_trainee(rows);
  for (size_t t = 0; t < by.size(); ++t) {
    plot::Series s, e;
    s.label = e.label = by[t].first;
    s.color = e.color = plot::palette(static_cast<int>(t));
    s.marker = e.marker = plot::Marker::Circle;
    for (size_t k = 0; k < by[t].second.size(); ++k) {
      const MetricsRow& r = rows[by[t].second[k]];
      s.x.push_back(static_cast<double>(k + 1));
      s.y.push_back(r.score);
      e.x.push_back(static_cast<double>(k + 1));
      e.y.push_back(r.mean_error_mm);
    }
    most = std::max(most, by[t].second.size());
    score_curve.series.push_back(s);
    err_curve.series.push_back(e);
  }
  const double x_hi = static_cast<double>(most) + 0.5;
  score_curve.x = {"attempt", false, 0.5, x_hi};
  score_curve.y = {"score", false, 0.0, 100.0};
  score_curve.legend = plot::LegendPos::BottomRight;
  err_curve.x = {"attempt", false, 0.5, x_hi};
  err_curve.y = {"mean targeting error [mm]", false, 0.0, err_hi};
  err_curve.series.push_back(horizontal(robot, 0.5, x_hi, "robot 1.0 mm", green));
  err_curve.series.push_back(horizontal(freehand, 0.5, x_hi, "freehand 9.0 mm", red));

  RgbImage img;
  img.width = 2 * kPanelW;
  img.height = 2 * kPanelH;
  img.pixels.assign(static_cast<size_t>(img.width) * img.height * 3, 255);
  blit(img, plot::render(score_hist, kPanelW, kPanelH), 0, 0);
  blit(img, plot::render(err_hist, kPanelW, kPanelH), kPanelW, 0);
  blit(img, plot::render(score_curve, kPanelW, kPanelH), 0, kPanelH);
  blit(img, plot::render(err_curve, kPanelW, kPanelH), kPanelW, kPanelH);
  return img;
}

}  // namespace ps::app
