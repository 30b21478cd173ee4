// Sessions of a class read back from metrics.json (what `prostatesim report` merges): a file
// written by metrics_json() parses to the same figures, sessions group per trainee in order, and
// a missing or garbled file is refused naming the file and the field.
#include "engine/metrics/class_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps {
namespace {

namespace fs = std::filesystem;

SessionReport sample_report(double error_m) {
  SessionReport r;
  r.scenario = "biopsy";
  r.duration = 2.0;
  r.procedure_time = 1.25;
  NeedleMetrics n;
  n.name = "n";
  n.scored = true;
  n.error = error_m;
  n.punctures = 2;
  r.needles.push_back(n);
  r.mean_error = r.max_error = error_m;
  r.punctures = 2;
  r.reinsertions = 1;
  r.structures_hit = 1;
  r.planned_sites = {"right mid lateral"};
  r.coverage = 1.0;
  return r;
}

fs::path temp_root(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("ps_class_report_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write_session(const fs::path& dir, const std::string& trainee, const std::string& session, double error_m) {
  fs::create_directories(dir);
  const SessionReport r = sample_report(error_m);
  write_file_atomic((dir / "metrics.json").string(), metrics_json(r, score_session(r), {trainee, session}));
}

TEST(MetricsJson, RoundTripOfTheTabulatedFields) {
  const SessionReport r = sample_report(4e-3);
  const Score sc = score_session(r);
  // 100 - 4 x 4 mm - 10 (one structure) - 3 (one re-insertion) - 0 (full coverage)
  EXPECT_NEAR(sc.value, 71.0, 1e-9);
  const MetricsRow row = parse_metrics_json(metrics_json(r, sc, {"bob", "s01"}), "m.json");
  EXPECT_EQ(row.trainee, "bob");
  EXPECT_EQ(row.session, "s01");
  EXPECT_EQ(row.scenario, "biopsy");
  EXPECT_NEAR(row.score, 71.0, 1e-9);
  EXPECT_NEAR(row.mean_error_mm, 4.0, 1e-9);
  EXPECT_NEAR(row.procedure_time_s, 1.25, 1e-12);
  EXPECT_EQ(row.punctures, 2);
  EXPECT_EQ(row.reinsertions, 1);
  EXPECT_EQ(row.structures_hit, 1);
  EXPECT_NEAR(row.coverage, 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(row.seed_error_mean_mm)) << "no seeds: null";
}

TEST(ClassReport, LoadsEverySessionBelowAFolderAndOrdersEachTrainee) {
  const fs::path root = temp_root("ok");
  write_session(root / "class" / "bob_2", "bob", "2026-12-01T10", 3e-3);
  write_session(root / "class" / "bob_1", "bob", "2026-11-30T10", 8e-3);
  write_session(root / "class" / "eve_1", "eve", "2026-11-30T11", 2e-3);
  write_session(root / "single", "ann", "1", 1e-3);
  const auto rows = load_sessions({(root / "class").string(), (root / "single").string()});
  ASSERT_EQ(rows.size(), 4u);
  const auto by = sessions_by_trainee(rows);
  ASSERT_EQ(by.size(), 3u);
  EXPECT_EQ(by[1].first, "bob");
  ASSERT_EQ(by[1].second.size(), 2u);
  EXPECT_NEAR(rows[by[1].second[0]].mean_error_mm, 8.0, 1e-9) << "first attempt by session name";
  EXPECT_NEAR(rows[by[1].second[1]].mean_error_mm, 3.0, 1e-9);
  const std::string csv = sessions_csv(rows);
  EXPECT_EQ(csv.rfind("trainee,session,attempt,scenario,score,mean_error_mm,", 0), 0u);
  EXPECT_NE(csv.find("bob,2026-11-30T10,1,biopsy,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("bob,2026-12-01T10,2,biopsy,"), std::string::npos) << csv;
  fs::remove_all(root);
}

TEST(ClassReport, BadInputNamesTheFileAndTheField) {
  const fs::path root = temp_root("bad");
  write_session(root / "a", "bob", "1", 3e-3);
  auto expect_error = [&](const std::string& content, const std::string& field) {
    fs::create_directories(root / "b");
    std::ofstream(root / "b" / "metrics.json") << content;
    try {
      load_sessions({(root / "a").string(), (root / "b").string()});
      ADD_FAILURE() << "accepted: " << content;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), (root / "b" / "metrics.json").string());
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  std::string good;
  {
    std::ifstream in(root / "a" / "metrics.json");
    good.assign(std::istreambuf_iterator<char>(in), {});
  }
  expect_error("{ not json", "");
  std::string no_score = good;
  no_score.replace(no_score.find("\"score\":"), 8, "\"scoreX\":");
  expect_error(no_score, "score");
  std::string text_error = good;
  const size_t at = text_error.find("\"mean_error_mm\": ") + 17;
  text_error.replace(at, text_error.find(',', at) - at, "\"far\"");
  expect_error(text_error, "targeting.mean_error_mm");
  try {
    load_sessions({(root / "nothing_here").string()});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing_here"), std::string::npos);
  }
  fs::create_directories(root / "empty");
  EXPECT_THROW(load_sessions({(root / "empty").string()}), InputError);
  fs::remove_all(root);
}

}  // namespace
}  // namespace ps
