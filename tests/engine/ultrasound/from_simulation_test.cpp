// engine/ultrasound/from_simulation.cpp: the probe pose a snapshot shows (what the app's
// ultrasound thread and the replay's us_* views image from) is the probe tool's own frame.
#include "engine/ultrasound/from_simulation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/realtime/lockstep.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"
#include "engine/tools/probe/probe.h"

namespace ps {
namespace {

void expect_near(const Vec3& a, const Vec3& b, double tol, const char* what) {
  EXPECT_LT((a - b).norm(), tol) << what << ": " << a.transpose() << " vs " << b.transpose();
}

TEST(UltrasoundFromSnapshot, ProbeViewMatchesTheProbeToolAtSeveralRolls) {
  for (double roll_deg : {0.0, 25.0, -40.0}) {
    ScenarioSpec spec = parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
    ASSERT_TRUE(spec.probe);
    spec.probe->pose.roll = roll_deg * M_PI / 180.0;
    Scene scene = build_scene(spec);
    LockstepRunner run(*scene.sim);
    const Snapshot& snap = run.snapshot();
    const auto* probe = scene.tools.as<ProbeTool>();
    ASSERT_NE(probe, nullptr);
    const us::ProbeView truth = us::probe_view(probe->frame(), probe->spec().radius);
    us::ProbeView v;
    ASSERT_TRUE(us::probe_view_from_snapshot(snap, v));
    expect_near(v.tip_centre, truth.tip_centre, 1e-9, "tip centre");
    expect_near(v.axis, truth.axis, 1e-9, "axis");
    expect_near(v.anterior, truth.anterior, 1e-9, "anterior");
    expect_near(v.lateral, truth.lateral, 1e-9, "lateral");
    EXPECT_NEAR(v.radius, truth.radius, 1e-12);
  }
}

TEST(UltrasoundFromSnapshot, NoProbeInTheSnapshotIsReported) {
  Snapshot snap;
  us::ProbeView v;
  v.radius = 0.123;
  EXPECT_FALSE(us::probe_view_from_snapshot(snap, v));
  EXPECT_EQ(v.radius, 0.123);  // left as it was
}

TEST(UltrasoundFromSnapshot, GuideDashesGiveOneOverlayLine) {
  Scene scene = load_scene(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml");
  LockstepRunner run(*scene.sim);
  const Snapshot& snap = run.snapshot();
  us::ProbeView v;
  ASSERT_TRUE(us::probe_view_from_snapshot(snap, v));
  us::UltrasoundScene sc;
  us::scene_from_snapshot(snap, v, sc);
  int guides = 0;
  for (const auto& o : sc.overlays) guides += o.kind == us::OverlayLine::Guide;
  EXPECT_EQ(guides, 1);
  EXPECT_EQ(sc.particle_count * 3, static_cast<int>(snap.x.size()));
}

}  // namespace
}  // namespace ps
