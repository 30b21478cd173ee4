#include "engine/metrics/class_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/util/error.h"

namespace ps {

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw InputError(p.string(), 0, "", "cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string cell(double v, const char* f = "%.4g") {
  if (std::isnan(v)) return "";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::vector<MetricsRow> load_sessions(const std::vector<std::string>& folders) {
  std::vector<MetricsRow> rows;
  for (const std::string& f : folders) {
    const fs::path dir(f);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(f, 0, "", "not a folder");
    std::vector<fs::path> files;
    if (fs::exists(dir / "metrics.json")) {
      files.push_back(dir / "metrics.json");
    } else {
      for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->path().filename() == "metrics.json") files.push_back(it->path());
      std::sort(files.begin(), files.end());
    }
    if (files.empty()) throw InputError(f, 0, "metrics.json", "no metrics.json in this folder or below it");
    for (const fs::path& p : files) rows.push_back(parse_metrics_json(read_file(p), p.string()));
  }
  return rows;
}

std::vector<std::pair<std::string, std::vector<int>>> sessions_by_trainee(const std::vector<MetricsRow>& rows) {
  std::map<std::string, std::vector<int>> by;
  for (size_t i = 0; i < rows.size(); ++i) by[rows[i].trainee.empty() ? "(unnamed)" : rows[i].trainee].push_back(static_cast<int>(i));
  std::vector<std::pair<std::string, std::vector<int>>> out;
  for (auto& [t, idx] : by) {
    std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return rows[a].session < rows[b].session; });
    out.emplace_back(t, idx);
  }
  return out;
}

std::string sessions_csv(const std::vector<MetricsRow>& rows) {
  std::vector<int> attempt(rows.size(), 0);
  for (const auto& [t, idx] : sessions_by_trainee(rows))
    for (size_t k = 0; k < idx.size(); ++k) attempt[idx[k]] = static_cast<int>(k) + 1;
  std::string s =
      "trainee,session,attempt,scenario,score,mean_error_mm,max_error_mm,procedure_time_s,needles,punctures,reinsertions,"
      "structures_hit,cores,coverage,lesions_targeted,lesions_missed,seed_error_mean_mm,seeds_outside_gland,file\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const MetricsRow& r = rows[i];
    s += csv_text(r.trainee) + "," + csv_text(r.session) + "," + std::to_string(attempt[i]) + "," + csv_text(r.scenario) + "," +
         cell(r.score, "%.2f") + "," + cell(r.mean_error_mm) + "," + cell(r.max_error_mm) + "," + cell(r.procedure_time_s) + "," +
         std::to_string(r.needles) + "," + std::to_string(r.punctures) + "," + std::to_string(r.reinsertions) + "," +
         std::to_string(r.structures_hit) + "," + std::to_string(r.cores) + "," + cell(r.coverage) + "," +
         std::to_string(r.lesions_targeted) + "," + std::to_string(r.lesions_missed) + "," + cell(r.seed_error_mean_mm) + "," +
         std::to_string(r.seeds_outside_gland) + "," + csv_text(r.file) + "\n";
  }
  return s;
}

}  // namespace ps
