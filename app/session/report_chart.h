// The class summary picture of `prostatesim report` (docs/batch.md): four charts on one page,
//   score distribution | mean targeting error distribution (with Han et al. 2012: robot 1.0 mm,
//   -------------------+  freehand urologists 9.0 mm)
//   score per attempt, one line per trainee | mean error per attempt, one line per trainee
// as an RGB image (rows top-down) for write_png_atomic.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/metrics/metrics_json.h"

namespace ps::app {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;     // width * height * 3
};

RgbImage render_report_chart(const std::vector<MetricsRow>& rows);

}  // namespace ps::app
