// Session score (docs/metrics.md): 100 points less documented penalties, clamped to [0, 100].
//   targeting    min(40, 4 x mean error [mm])          (9.0 mm freehand -> 36, 1.0 mm robot -> 4)
//   structures   10 per structure hit (urethra, rectal wall, bladder, bone)
//   reinsertion  3 per re-insertion
//   coverage     20 x (1 - coverage of the planned biopsy sites)      (when sites are planned)
//   lesion       10 per targeted lesion whose core holds no tumour
//   seeds        min(20, 2 x mean seed error [mm]) + 5 per seed outside the gland
//   dosimetry    40 x (planned - achieved prostate V100, when positive) + 10 if the urethra D10
//                reaches 150 % of the prescription + 10 if the rectum D2cc reaches it (each only
//                when the plan kept below it): the TG-43U1 dose of the seeds where they are
// A session in which no needle reached its decisive moment, or whose simulation faulted,
// scores 0 (term "incomplete").
// Scale (Han et al., J Urol 2012, pelvic mock-ups): freehand urologists 9.0 mm mean targeting
// error (clustered cores), probe-holding robot 1.0 mm.
#pragma once
#include <string>
#include <vector>

#include "engine/metrics/session_metrics.h"

namespace ps {

inline constexpr double kHanFreehandError = 9.0e-3;  // [m]
inline constexpr double kHanRobotError = 1.0e-3;     // [m]

struct ScoreTerm {
  std::string name;
  double points = 0.0;              // subtracted from 100
  std::string detail;
};

struct Score {
  double value = 0.0;               // [0, 100]
  std::vector<ScoreTerm> terms;
};

Score score_session(const SessionReport& r);

// Where a mean targeting error lies on the Han et al. scale: 0 at the robot's 1.0 mm, 1 at the
// freehand 9.0 mm (not clamped: < 0 better than the robot, > 1 worse than freehand).
double han_scale_position(double mean_error_m);
// One line for the trainee, e.g. "3.2 mm: between the robot (1.0 mm) and freehand urologists (9.0 mm)".
std::string han_scale_text(double mean_error_m);

}  // namespace ps
