#include "engine/metrics/score.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ps {

namespace {
std::string fmt(const char* f, double a, double b = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}
}  // namespace

Score score_session(const SessionReport& r) {
  Score s;
  const bool complete = !r.faulted && !std::isnan(r.mean_error);
  if (!complete) {
    s.terms.push_back({"incomplete", 100.0, r.faulted ? "the simulation faulted" : "no needle reached its target region"});
    s.value = 0.0;
    return s;
  }
  const double e_mm = 1e3 * r.mean_error;
  s.terms.push_back({"targeting", std::min(40.0, 4.0 * e_mm), fmt("mean error %.2f mm x 4 (max 40)", e_mm)});
  s.terms.push_back({"structures", 10.0 * r.structures_hit, fmt("%.0f structure(s) hit x 10", r.structures_hit)});
  // through the capsule: common in the lateral and base cores of a 22 mm throw and harmless in
  // itself (periprostatic tissue in the core), unlike the structures above; weighed lightly so that
  // a trainee learns to fire nearer the capsule (provisional: no source gives a weight)
  if (r.capsule_exits > 0)
    s.terms.push_back({"capsule", 1.0 * r.capsule_exits, fmt("%.0f exit(s) through the capsule x 1", r.capsule_exits)});
  s.terms.push_back({"reinsertion", 3.0 * r.reinsertions, fmt("%.0f re-insertion(s) x 3", r.reinsertions)});
  if (!std::isnan(r.coverage))
    s.terms.push_back({"coverage", 20.0 * (1.0 - r.coverage), fmt("%.0f %% of the planned sites cored", 100.0 * r.coverage)});
  if (r.cores_outside_gland > 0)
    s.terms.push_back({"outside", 5.0 * r.cores_outside_gland, fmt("%.0f core(s) outside the gland x 5", r.cores_outside_gland)});
  if (r.lesions_targeted > 0)
    s.terms.push_back({"lesion", 10.0 * r.lesions_missed, fmt("%.0f of %.0f targeted lesion(s) missed", r.lesions_missed, r.lesions_targeted)});
  if (!std::isnan(r.seed_error_mean)) {
    const double se = 1e3 * r.seed_error_mean;
    s.terms.push_back({"seeds", std::min(20.0, 2.0 * se) + 5.0 * r.seeds_outside_gland,
                       fmt("mean seed error %.2f mm x 2 (max 20), %.0f outside the gland x 5", se, r.seeds_outside_gland)});
  }
  if (r.dosimetry.computed) {
    // the dose delivered against the dose planned (docs/dosimetry.md)
    const auto& p = r.dosimetry.planned;
    const auto& a = r.dosimetry.achieved;
    const double rx = r.dosimetry.prescription_gy;
    const double lost = std::max(0.0, p.prostate_v100 - a.prostate_v100);
    const bool urethra = a.urethra_d10_gy >= 1.5 * rx && p.urethra_d10_gy < 1.5 * rx;
    const bool rectum = a.rectum_d2cc_gy >= rx && p.rectum_d2cc_gy < rx;
    char buf[200];
    std::snprintf(buf, sizeof buf, "prostate V100 %.1f %% of planned %.1f %% (40 x the shortfall)%s%s", 100.0 * a.prostate_v100,
                  100.0 * p.prostate_v100, urethra ? ", urethra D10 >= 150 % x 10" : "", rectum ? ", rectum D2cc >= Rx x 10" : "");
    s.terms.push_back({"dosimetry", 40.0 * lost + (urethra ? 10.0 : 0.0) + (rectum ? 10.0 : 0.0), buf});
  }
  double v = 100.0;
  for (const ScoreTerm& t : s.terms) v -= t.points;
  s.value = std::clamp(v, 0.0, 100.0);
  return s;
}

double han_scale_position(double e) { return (e - kHanRobotError) / (kHanFreehandError - kHanRobotError); }

std::string han_scale_text(double e) {
  if (std::isnan(e)) return "no targeting error measured";
  const double mm = 1e3 * e;
  std::string where;
  if (e <= kHanRobotError) where = "at or better than the probe-holding robot (1.0 mm)";
  else if (e < kHanFreehandError) where = "between the robot (1.0 mm) and freehand urologists (9.0 mm)";
  else where = "at or worse than freehand urologists (9.0 mm)";
  return fmt("%.1f mm: ", mm) + where + " (Han et al., J Urol 2012)";
}

}  // namespace ps
