// metrics.json: a session's metrics and score (written by insert / run / replay, read by
// `prostatesim report`). Lengths in mm, forces in N, times in s; null where not measured.
#pragma once
#include <string>

#include "engine/metrics/score.h"
#include "engine/metrics/session_metrics.h"

namespace ps {

inline constexpr int kMetricsFormatVersion = 1;

struct SessionInfo {
  std::string trainee;              // who (report: learning curve per trainee)
  std::string session;              // which attempt; sessions of a trainee sort by this string
};

std::string metrics_json(const SessionReport& r, const Score& score, const SessionInfo& info);

// The fields of a metrics.json that `report` tabulates.
struct MetricsRow {
  std::string file, trainee, session, scenario;
  double score = 0.0;
  double mean_error_mm = 0.0, max_error_mm = 0.0;   // NAN: no needle scored
  double procedure_time_s = 0.0;
  int needles = 0, structures_hit = 0, reinsertions = 0, punctures = 0;
  double coverage = 0.0;            // NAN: no planned sites
  int cores = 0, lesions_targeted = 0, lesions_missed = 0;
  double seed_error_mean_mm = 0.0;  // NAN: no seed
  int seeds_outside_gland = 0;
};

// Parses one metrics.json; InputError naming `file` and the field at fault (missing, wrong type,
// not JSON, other format version).
MetricsRow parse_metrics_json(const std::string& text, const std::string& file);

}  // namespace ps
