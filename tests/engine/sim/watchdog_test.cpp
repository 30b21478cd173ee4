// Tests for engine/sim/watchdog.cpp, and the CI-sized soak: the watchdog must stay quiet on a
// healthy run and name the particle and the time for each kind of trouble it watches.
#include "engine/sim/watchdog.h"

#include <gtest/gtest.h>

#include "engine/step/simulation.h"
#include "tests/engine/test_scenes.h"

namespace ps {
namespace {

TEST(Watchdog, QuietOnAHealthySoak) {
  // CI-sized soak: 2 s of an incompressible cube sagging under gravity, checked every tick.
  const auto m = test::compile_text(test::cube_yaml(40, 10, true));
  Simulation sim(m);
  const Watchdog dog(*m);
  for (int k = 0; k < 2000; ++k) {
    ASSERT_TRUE(sim.tick());
    const WatchFinding f = dog.check(*m, sim.state());
    ASSERT_TRUE(f.ok) << f.describe(*m);
  }
}

TEST(Watchdog, NamesAParticleThatIsTooFast) {
  const auto m = test::compile_text(test::cube_yaml(40, 10));
  State s = make_state(*m);
  s.time = 0.25;
  s.v[37] = Vec3(0, 0, 20.0);  // [m/s] above the 10 m/s limit
  const WatchFinding f = Watchdog(*m).check(*m, s);
  EXPECT_FALSE(f.ok);
  EXPECT_EQ(f.what, "energy growth");
  EXPECT_EQ(f.particle, 37);
  const std::string d = f.describe(*m);
  EXPECT_NE(d.find("particle 37"), std::string::npos) << d;
  EXPECT_NE(d.find("t=0.25"), std::string::npos) << d;
}

TEST(Watchdog, NamesAParticleThatLeftTheScene) {
  const auto m = test::compile_text(test::cube_yaml(40, 10));
  State s = make_state(*m);
  s.x[5] += Vec3(0.2, 0, 0);  // 200 mm outside
  const WatchFinding f = Watchdog(*m).check(*m, s);
  EXPECT_EQ(f.what, "left the scene");
  EXPECT_EQ(f.particle, 5);
}

// The margin is the scene's (watchdog.leave_margin_mm, default 50 mm), unless the caller gives one.
TEST(Watchdog, TheLeaveMarginIsTheScenesOwn) {
  const auto def = test::compile_text(test::cube_yaml(40, 10));
  const auto wide = test::compile_text("watchdog: {leave_margin_mm: 200}\n" + test::cube_yaml(40, 10));
  EXPECT_DOUBLE_EQ(def->leave_margin, 0.05);
  EXPECT_DOUBLE_EQ(wide->leave_margin, 0.2);
  for (const auto& m : {def, wide}) {
    State s = make_state(*m);
    s.x[5] += Vec3(0.1, 0, 0);  // 100 mm outside (x max of the cube's rest box is 40 mm)
    const WatchFinding f = Watchdog(*m).check(*m, s);
    EXPECT_EQ(f.ok, m == wide) << f.describe(*m);
    WatchLimits narrow;
    narrow.leave_margin = 0.01;  // [m] the caller's wins
    EXPECT_EQ(Watchdog(*m, narrow).check(*m, s).what, "left the scene");
  }
  EXPECT_THROW(test::compile_text("watchdog: {leave_margin_mm: 0}\n" + test::cube_yaml(40, 10)), InputError);
  EXPECT_THROW(test::compile_text("watchdog: {margin_mm: 100}\n" + test::cube_yaml(40, 10)), InputError);
}

TEST(Watchdog, SeesNaNAndVolumeDrift) {
  const auto m = test::compile_text(test::cube_yaml(40, 10, true));
  State s = make_state(*m);
  s.v[3].x() = std::nan("");
  EXPECT_EQ(Watchdog(*m).check(*m, s).what, "not finite");
  State t = make_state(*m);
  for (auto& x : t.x) x *= 1.1;  // 33 % more volume than the target
  const WatchFinding f = Watchdog(*m, {10.0, 0.05, 1.0}).check(*m, t);
  EXPECT_EQ(f.what, "volume drift") << f.describe(*m);
  EXPECT_NEAR(f.value, 1.1 * 1.1 * 1.1 - 1.0, 1e-6);
}

TEST(Watchdog, RecordsTheWorstValuesItSaw) {
  const auto m = test::compile_text(test::cube_yaml(40, 10, true));
  int p = 0;
  while (m->inv_mass[p] == 0) ++p;  // a free particle
  State s = make_state(*m);
  s.time = 0.5;
  s.v[p] = Vec3(0, 0, 2.0);           // [m/s]
  s.x[p] += Vec3(0.003, 0, 0);        // [m]
  const Watchdog dog(*m, {10.0, 0.5, 0.05});
  WatchPeaks peaks;
  ASSERT_TRUE(dog.check(*m, s, &peaks).ok);
  EXPECT_EQ(peaks.max_speed, 2.0);
  EXPECT_EQ(peaks.fastest, p);
  EXPECT_EQ(peaks.max_speed_time, 0.5);
  EXPECT_NEAR(peaks.max_kinetic, 0.5 * 2.0 * 2.0 / m->inv_mass[p], 1e-15);
  EXPECT_NEAR(peaks.max_displacement, 0.003, 1e-15);
  EXPECT_EQ(peaks.farthest, p);
  EXPECT_GT(peaks.max_volume_drift, 0.0);  // one vertex moved 3 mm
  EXPECT_LT(peaks.min_margin, 0.05);       // the cube's own particles sit on its bounding box
  // a calmer tick keeps the peaks
  s.time = 0.6;
  s.v[p] = Vec3(0, 0, 1.0);
  s.x[p] = m->rest_pos[p];
  ASSERT_TRUE(dog.check(*m, s, &peaks).ok);
  EXPECT_EQ(peaks.max_speed, 2.0);
  EXPECT_EQ(peaks.max_speed_time, 0.5);
  EXPECT_EQ(peaks.checks, 2);
}

}  // namespace
}  // namespace ps
