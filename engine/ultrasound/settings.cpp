#include "engine/ultrasound/settings.h"

#include <cmath>
#include <cstdio>

#include "engine/util/error.h"

namespace ps::us {

UltrasoundSettings settings_for_probe(const ProbeSpec& probe) {
  UltrasoundSettings s;
  s.convex_radius = probe.radius;
  return s;
}

namespace {
// value in [lo, hi] (in display units `unit`, with `scale` from SI), else InputError naming field
void check(const std::string& file, const char* field, double si, double scale, double lo, double hi, const char* unit) {
  const double v = si * scale;
  if (!std::isfinite(v) || v < lo || v > hi) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%g %s is out of range [%g, %g] %s", v, unit, lo, hi, unit);
    throw InputError(file, 0, std::string("ultrasound.") + field, buf);
  }
}
}  // namespace

void validate(const UltrasoundSettings& s, const std::string& file) {
  check(file, "frequency_mhz", s.frequency, 1e-6, 1.0, 20.0, "MHz");
  check(file, "gain_db", s.gain_db, 1.0, -60.0, 60.0, "dB");
  check(file, "depth_mm", s.depth, 1e3, 10.0, 150.0, "mm");
  check(file, "dynamic_range_db", s.dynamic_range_db, 1.0, 20.0, 100.0, "dB");
  check(file, "tgc_db_cm_mhz", s.tgc_db_cm_mhz, 1.0, 0.0, 3.0, "dB/(cm MHz)");
  check(file, "convex_radius_mm", s.convex_radius, 1e3, 3.0, 50.0, "mm");
  check(file, "fov_deg", s.fov, 180.0 / 3.141592653589793, 10.0, 180.0, "deg");
  check(file, "transverse_back_mm", s.transverse_back, 1e3, 0.0, 100.0, "mm");
  check(file, "width_mm", s.linear_width, 1e3, 10.0, 120.0, "mm");
  check(file, "linear_front_mm", s.linear_front, 1e3, 0.0, 100.0, "mm");
  check(file, "slice_thickness_mm", s.slice_thickness, 1e3, 0.1, 10.0, "mm");
  check(file, "bandwidth", s.bandwidth, 1.0, 0.05, 1.5, "(fraction of the centre frequency)");
  check(file, "focus_mm", s.focus_depth, 1e3, 2.0, 150.0, "mm");
  check(file, "f_number", s.f_number, 1.0, 1.0, 10.0, "(focal depth / aperture)");
  check(file, "rx_aperture_mm", s.rx_aperture, 1e3, 2.0, 80.0, "mm");
  check(file, "width_px", s.width, 1.0, 16, 4096, "px");
  check(file, "height_px", s.height, 1.0, 16, 4096, "px");
}

}  // namespace ps::us
