// `prostatesim insert` as a user runs it (app/cmd_insert.cpp): the per-needle force-vs-depth CSV
// and the event, seed and core files; bad needle input exits 2 naming file:line and the field,
// writing nothing; an absurd push is clamped and reported, not a blow-up.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app/run_cli.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace {

namespace fs = std::filesystem;
using ps::test::BlockOptions;
using ps::test::block_yaml;
using ps::test::run_cli;
using ps::test::vertical_needle;

fs::path temp_dir(const std::string& name) { return ps::test::cli_temp_dir("insert_" + name); }

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

long lines(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }

TEST(Insert, WritesForceDepthPerNeedleEventsSeedsAndCores) {
  const fs::path dir = temp_dir("ok");
  const fs::path scen = dir / "block.yaml";
  std::ofstream(scen) << block_yaml(BlockOptions{},
                                    vertical_needle("a", 1.3, 0.9, "[[0, 0], [0.6, 12], [0.7, 12], [0.9, 6]]", "      seeds_mm: [9]\n") +
                                        vertical_needle("b", -6.7, 0.9, "[[0, 0], [0.6, 14]]"));
  const fs::path out = dir / "out";
  const auto r = run_cli("insert " + scen.string() + " --duration 0.9 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"force_depth_a.csv", "force_depth_b.csv", "needle_events.csv", "seeds.csv", "cores.csv"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const std::string fd = read(out / "force_depth_a.csv");
  EXPECT_EQ(fd.rfind("time_s,depth_mm,plan_depth_mm,axial_force_n,", 0), 0u);
  EXPECT_EQ(lines(fd), 1 + 900) << "one row per tick";
  const std::string ev = read(out / "needle_events.csv");
  EXPECT_EQ(ev.rfind("time_s,needle,event,component,node,depth_mm,force_n,", 0), 0u);
  EXPECT_NE(ev.find(",a,puncture,tissue,"), std::string::npos) << ev;
  EXPECT_NE(ev.find(",b,puncture,tissue,"), std::string::npos) << ev;
  EXPECT_NE(ev.find(",a,seed,tissue,"), std::string::npos) << ev;
  EXPECT_EQ(lines(read(out / "seeds.csv")), 2) << "header + the one seed";
  EXPECT_NE(r.out.find("a puncture tissue"), std::string::npos) << r.out;
  // atomic writes leave no temporary file behind
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_TRUE(e.path().extension() == ".csv" || e.path().filename() == "metrics.json" || e.path().filename() == "report.png")
        << e.path();
}

TEST(Insert, CoresCsvNamesTheClinicalSiteOfEachCore) {
  // the biopsy block (a gland box over a tumour box) with prostate zones on the gland: the gun
  // fires 22 mm at 0.5 s from (1.3, 0.9) mm down -z, right of the midline (x > 0 is the
  // patient's right, RAS), through the gland into the tumour
  std::string y = ps::test::biopsy_yaml();
  y.replace(y.find("needles:"), 0, "prostate_zones: {component: prostate, peripheral_depth_mm: 4}\n");
  const fs::path dir = temp_dir("cores");
  const fs::path scen = dir / "biopsy.yaml";
  std::ofstream(scen) << y;
  const fs::path out = dir / "out";
  const auto r = run_cli("insert " + scen.string() + " --duration 0.6 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string cores = read(out / "cores.csv");
  EXPECT_EQ(cores.rfind("needle,taken,time_s,component,particles,tumour_particles,tumour_length_mm,notch_length_mm,site\n", 0), 0u)
      << cores;
  // one row per component and tag of the core, each ending with the same site label
  const std::string row = cores.substr(cores.find('\n') + 1, cores.find('\n', cores.find('\n') + 1) - cores.find('\n') - 1);
  EXPECT_EQ(row.rfind("gun,1,", 0), 0u) << row;
  const std::string site = row.substr(row.rfind(',') + 1);
  EXPECT_EQ(site.rfind("right ", 0), 0u) << "site '" << site << "'";
  EXPECT_NE(site.find(" ("), std::string::npos) << "the zone in parentheses: '" << site << "'";
  size_t rows_with_site = 0;
  for (size_t at = cores.find('\n'); (at = cores.find("," + site + "\n", at)) != std::string::npos; ++at) ++rows_with_site;
  EXPECT_EQ(static_cast<long>(rows_with_site), lines(cores) - 1) << cores;
}

TEST(Insert, BadNeedleInputExits2NamingFileLineFieldAndWritesNothing) {
  const fs::path dir = temp_dir("bad");
  struct Case {
    std::string needles, field;
  };
  const std::vector<Case> cases = {
      {vertical_needle("far", 300, 0, "[[0, 0], [1, 50]]"), "needles.instruments[0].start_mm"},  // outside the scene
      {"    - {name: n, length_mm: 0, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n", "needles.instruments[0].length_mm"},
      {"    - {name: n, length_mm: -20, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n", "needles.instruments[0].length_mm"},
      {"    - {name: n, gauge: -18, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n", "needles.instruments[0].gauge"},
      {"    - {name: n, diameter_mm: 0, start_mm: [0, 0, 1], direction: [0, 0, -1]}\n", "needles.instruments[0].diameter_mm"},
      {vertical_needle("n", 1.3, 0.9, "[[0, 0], [1, 10]]", "      friction_radius_mm: 0.1\n"),
       "needles.instruments[0].friction_radius_mm"},
      {vertical_needle("n", 1.3, 0.9, "[[0, 0], [1, 10]]", "      cutting_radius_mm: 400\n"),
       "needles.instruments[0].cutting_radius_mm"},
      {vertical_needle("n", 1.3, 0.9, "[[0, 0], [1, 10]]", "      seeds_mm: [5, 150]\n"), "needles.instruments[0].seeds_mm[1]"},
      {vertical_needle("n", 1.3, 0.9, "[[0, 0], [1, 10]]", "      seeds_mm: [5, 30]\n"), "needles.instruments[0].seeds_mm[1]"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const fs::path scen = dir / ("bad" + std::to_string(i) + ".yaml");
    std::ofstream(scen) << block_yaml(BlockOptions{}, cases[i].needles);
    const fs::path out = dir / ("out" + std::to_string(i));
    const auto r = run_cli("insert " + scen.string() + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << cases[i].field << ": " << r.out;
    EXPECT_NE(r.out.find("bad" + std::to_string(i) + ".yaml:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(cases[i].field), std::string::npos) << r.out;
    EXPECT_EQ(lines(r.out), 1) << "one error line: " << r.out;
    EXPECT_FALSE(fs::exists(out)) << "nothing written for " << cases[i].field;
  }
}

TEST(Insert, AbsurdPushIsClampedAndReportedNotABlowUp) {
  // the script asks for 90 mm in 1 ms: ~180 kN through the coupling spring
  const fs::path dir = temp_dir("absurd");
  const fs::path scen = dir / "absurd.yaml";
  std::ofstream(scen) << block_yaml(BlockOptions{}, vertical_needle("n", 1.3, 0.9, "[[0, 0], [0.1, 0], [0.101, 90]]"));
  const fs::path out = dir / "out";
  const auto r = run_cli("insert " + scen.string() + " --duration 0.2 --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("force_clamped"), std::string::npos) << r.out;
  EXPECT_NE(read(out / "needle_events.csv").find(",n,force_clamped,"), std::string::npos);
}

}  // namespace
