// The shipped 12-core script (config/scripts/biopsy_12core.yaml): an expert who aims only by moving
// the probe takes 12 cores with the one needle in the guide, at the 12 distinct sites of the
// scheme, each core's notch within a few millimetres of its site's centre, no structure hit, no
// refused command, no probe move lengthened, no watchdog finding, and the session scores at least
// 90. 26.6 s of simulated time at full resolution, about 20 s of wall time in a Release build: it
// runs by default (the same run by hand: `prostatesim replay config/biopsy.yaml --script
// config/scripts/biopsy_12core.yaml --report DIR`).
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <string>

#include "engine/metrics/metrics_options.h"
#include "engine/metrics/score.h"
#include "engine/metrics/session_metrics.h"
#include "engine/realtime/lockstep.h"
#include "engine/realtime/script.h"
#include "engine/sim/watchdog.h"
#include "engine/tools/needle/needle.h"

namespace ps {
namespace {

TEST(Biopsy12Core, TwelveCoresAtTwelveSitesScoreNinety) {
  const std::string dir = std::string(PROSTATESIM_SOURCE_DIR) + "/config/";
  Scene sc = load_scene(dir + "biopsy.yaml");
  const Script s = parse_script_file(dir + "scripts/biopsy_12core.yaml");
  CommandPlayer player(script_commands(s, sc));
  LockstepRunner run(*sc.sim);
  run.add_source(&player);
  const Watchdog dog(*sc.model);
  run.runner().set_watchdog(&dog);
  const auto& needles = *sc.tools.as<NeedleTool>();
  SessionMetrics metrics(*sc.model, needles, metrics_options_for(sc.spec, *sc.model));
  const int64_t end = static_cast<int64_t>(std::llround(s.duration / sc.model->dt));
  while (run.tick() < end) {
    ASSERT_TRUE(run.step()) << run.runner().fault_text();
    metrics.observe(needles, sc.sim->state());
  }
  EXPECT_EQ(run.applier().refused(), 0);
  for (int i = 0; i < run.applier().refusals().size(); ++i) ADD_FAILURE() << run.applier().refusals().at(i).describe();
  for (const std::string& l : scene_tool_reports(sc)) ADD_FAILURE() << "adjusted: " << l;
  const SessionReport rep = metrics.finish(needles, sc.sim->state());
  const Score score = score_session(rep);
  std::set<std::string> sites;
  int taken = 0;
  for (const CoreMetrics& c : rep.cores) {
    std::printf("core %.2f s: %-32s notch-site %.2f mm%s\n", c.time, c.site.c_str(), 1e3 * c.site_error, c.lesion_hit ? "  lesion" : "");
    if (!c.taken) continue;
    ++taken;
    EXPECT_LT(c.site_error, 3e-3) << c.site;
    sites.insert(c.site.substr(0, c.site.find(" (")));
  }
  for (const ScoreTerm& t : score.terms) std::printf("  -%.1f %s: %s\n", t.points, t.name.c_str(), t.detail.c_str());
  std::printf("score %.1f, coverage %.2f, mean error %.2f mm, structures %d, re-insertions %d, lesions %d/%d missed\n", score.value,
              rep.coverage, 1e3 * rep.mean_error, rep.structures_hit, rep.reinsertions, rep.lesions_missed, rep.lesions_targeted);
  EXPECT_EQ(taken, 12);
  EXPECT_EQ(sites.size(), 12u);
  EXPECT_DOUBLE_EQ(rep.coverage, 1.0);
  EXPECT_EQ(rep.cores_outside_gland, 0);
  EXPECT_EQ(rep.structures_hit, 0);
  EXPECT_GE(score.value, 90.0);
}

}  // namespace
}  // namespace ps
