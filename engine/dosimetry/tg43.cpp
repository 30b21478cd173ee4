#include "engine/dosimetry/tg43.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ps::dosimetry {

namespace {

// index i with x[i] <= v < x[i+1] (clamped to [0, n-2])
size_t bracket(const std::vector<double>& x, double v) {
  const auto it = std::upper_bound(x.begin(), x.end(), v);
  const size_t i = it == x.begin() ? 0 : static_cast<size_t>(it - x.begin()) - 1;
  return std::min(i, x.size() - 2);
}

}  // namespace

double geometry_function(double r_cm, double theta_rad, double length_cm) {
  const double s = std::abs(std::sin(theta_rad)), c = std::abs(std::cos(theta_rad));
  double rho = r_cm * s;
  const double z = r_cm * c, h = 0.5 * length_cm;
  if (rho < 1e-9 * r_cm) {
    if (z > 1.01 * h) return 1.0 / (r_cm * r_cm - h * h);
    rho = 1e-3;  // on the axis inside the active length: finite, very high (inside the seed)
  }
  const double beta = std::atan2(z + h, rho) - std::atan2(z - h, rho);
  return beta / (length_cm * rho);
}

double radial_dose(const SourceModel& s, double r_cm) {
  const auto& x = s.g_r_cm;
  const auto& y = s.g;
  if (r_cm <= x.front()) return y.front();
  const size_t n = x.size();
  if (r_cm >= x.back()) {  // log-linear on the last two nodes
    const double k = std::log(y[n - 1] / y[n - 2]) / (x[n - 1] - x[n - 2]);
    return y[n - 1] * std::exp(k * (r_cm - x[n - 1]));
  }
  const size_t i = bracket(x, r_cm);
  const double t = (r_cm - x[i]) / (x[i + 1] - x[i]);
  return y[i] + t * (y[i + 1] - y[i]);
}

double anisotropy(const SourceModel& s, double r_cm, double theta_deg) {
  const auto& R = s.f_r_cm;
  const auto& T = s.f_theta_deg;
  const size_t nt = T.size();
  theta_deg = std::clamp(theta_deg, T.front(), T.back());
  const size_t j = bracket(T, theta_deg);
  const double u = (theta_deg - T[j]) / (T[j + 1] - T[j]);
  auto at_row = [&](size_t i) { return s.f[i * nt + j] + u * (s.f[i * nt + j + 1] - s.f[i * nt + j]); };
  if (r_cm <= R.front()) return at_row(0);
  const size_t i = bracket(R, r_cm);  // beyond the last radius: t > 1, linear on the last two
  const double t = (r_cm - R[i]) / (R[i + 1] - R[i]);
  return at_row(i) + t * (at_row(i + 1) - at_row(i));
}

double dose_rate_per_u(const SourceModel& s, double r_cm, double theta_rad) {
  r_cm = std::max(r_cm, kMinRadiusCm);
  const double g0 = geometry_function(1.0, 0.5 * std::numbers::pi, s.length_cm);
  double th = std::fmod(std::abs(theta_rad), std::numbers::pi);
  if (th > 0.5 * std::numbers::pi) th = std::numbers::pi - th;
  return s.lambda_cgy_h_u * geometry_function(r_cm, th, s.length_cm) / g0 * radial_dose(s, r_cm) *
         anisotropy(s, r_cm, th * 180.0 / std::numbers::pi);
}

double permanent_dose_factor(const SourceModel& s) { return s.half_life_d * 24.0 / std::numbers::ln2 / 100.0; }

}  // namespace ps::dosimetry
