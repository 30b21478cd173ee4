// A class of sessions (`prostatesim report`): every metrics.json under the given folders, one CSV
// row per session, and per trainee the sessions in order (the learning curve).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "engine/metrics/metrics_json.h"

namespace ps {

// metrics.json of each folder: the folder's own, else every one below it (sorted by path).
// InputError naming the folder when it holds none or does not exist, or naming the file and
// field of a missing or garbled metrics.json.
std::vector<MetricsRow> load_sessions(const std::vector<std::string>& folders);

// header: trainee,session,attempt,scenario,score,mean_error_mm,max_error_mm,procedure_time_s,
//         needles,punctures,reinsertions,structures_hit,cores,coverage,lesions_targeted,
//         lesions_missed,seed_error_mean_mm,seeds_outside_gland,file   (empty cell: not measured)
std::string sessions_csv(const std::vector<MetricsRow>& rows);

// Per trainee (sorted by name; "" shown as "(unnamed)"), the indices of its sessions ordered by
// session name: attempt k of a trainee is the k-th (1-based) of that list.
std::vector<std::pair<std::string, std::vector<int>>> sessions_by_trainee(const std::vector<MetricsRow>& rows);

}  // namespace ps
