// A device mapped to the TRUS probe (haptics/probe_source.h), with a synthetic device: the six
// device axes move the probe's insertion, offset, tilt, yaw and roll relative to where it was when
// the mapping took hold (no jump); a jump of the device is followed within the probe's speed
// limits (the probe never has to lengthen a move); the clutch re-centres; a disconnect leaves the
// probe where it was and says so; no command is refused. The mouse+keyboard device's arrows give
// rotation x / y.
#include "haptics/probe_source.h"

#include <gtest/gtest.h>

#include "engine/realtime/lockstep.h"
#include "engine/tools/probe/probe.h"
#include "haptics/mouse_keyboard.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps::haptics {
namespace {

class SyntheticDevice final : public Device {
 public:
  const char* name() const override { return "synthetic"; }
  bool poll(double, DeviceState& out) override {
    out = st;
    return st.connected;
  }
  DeviceState st;
};

const ProbeTool& probe_of(const Scene& sc) { return *sc.tools.as<ProbeTool>(); }

TEST(ProbeSource, SixAxesMoveThePoseRelativeToWhereItWas) {
  Scene sc = test::make_live_scene();
  ASSERT_GE(sc.tools.index<ProbeTool>(), 0);
  SyntheticDevice dev;
  dev.st.position = Vec3(0.3, -0.2, 0.1);  // anywhere: only motion counts
  dev.st.rotation = Vec3(0.5, 0.1, -1.0);
  ProbeSource src(sc, dev);
  LockstepRunner run(*sc.sim);
  run.add_source(&src);
  const ProbePose p0 = probe_of(sc).pose();
  ASSERT_TRUE(run.advance_to(5));
  EXPECT_EQ(probe_of(sc).pose().insertion, p0.insertion);  // no jump when the mapping takes hold
  const Vec3 x0 = dev.st.position, r0 = dev.st.rotation;
  for (int k = 1; k <= 100; ++k) {  // 5 mm deeper, 2 mm lateral device x, 1 mm device y over 0.1 s
    const double s = k / 100.0;
    dev.st.position = x0 + s * Vec3(0.002, 0.001, 0.005);
    dev.st.rotation = r0 + s * Vec3(0.05, -0.03, 0.1);
    ASSERT_TRUE(run.step()) << run.runner().fault_text();
  }
  ASSERT_TRUE(run.advance_to(run.tick() + 20));  // the last one-tick move completes
  const ProbePose& p = probe_of(sc).pose();
  // rectal frame of the scene: axis +z, anterior +y, lateral = axis x anterior = -x
  EXPECT_NEAR(p.insertion, p0.insertion + 0.005, 1e-12);
  EXPECT_NEAR(p.offset.x(), p0.offset.x() - 0.002, 1e-12);
  EXPECT_NEAR(p.offset.y(), p0.offset.y() + 0.001, 1e-12);
  EXPECT_NEAR(p.offset.z(), p0.offset.z(), 1e-12);
  EXPECT_NEAR(p.tilt, p0.tilt + 0.05, 1e-12);
  EXPECT_NEAR(p.yaw, p0.yaw - 0.03, 1e-12);
  EXPECT_NEAR(p.roll, p0.roll + 0.1, 1e-12);
  EXPECT_EQ(src.commands_sent(), 100);
  EXPECT_EQ(run.applier().refused(), 0);
  EXPECT_TRUE(probe_of(sc).reports().empty()) << probe_of(sc).reports().front();
}

TEST(ProbeSource, AJumpIsFollowedWithinTheSpeedLimitsAndTheClutchRecentres) {
  Scene sc = test::make_live_scene();
  SyntheticDevice dev;
  ProbeSource src(sc, dev);
  LockstepRunner run(*sc.sim);
  run.add_source(&src);
  ASSERT_TRUE(run.step());
  const ProbePose p0 = probe_of(sc).pose();
  const ProbeSpec& spec = *sc.spec.probe;
  dev.st.position.z() = 0.020;  // 20 mm at once
  ASSERT_TRUE(run.advance_to(11));
  const double per_tick = 0.95 * spec.max_speed * sc.model->dt / 1.5;
  EXPECT_NEAR(probe_of(sc).pose().insertion - p0.insertion, 10 * per_tick, 1e-9);
  ASSERT_TRUE(run.advance_to(400));
  EXPECT_NEAR(probe_of(sc).pose().insertion, p0.insertion + 0.020, 1e-12);
  EXPECT_TRUE(probe_of(sc).reports().empty()) << probe_of(sc).reports().front();  // never lengthened
  // clutch held: the device moves back, the probe does not; released: no jump
  dev.st.buttons = kButtonClutch;
  dev.st.position.z() = 0.0;
  ASSERT_TRUE(run.advance_to(420));
  dev.st.buttons = 0;
  ASSERT_TRUE(run.advance_to(440));
  EXPECT_NEAR(probe_of(sc).pose().insertion, p0.insertion + 0.020, 1e-12);
  dev.st.position.z() = -0.003;  // from the new centre: 3 mm back
  ASSERT_TRUE(run.advance_to(500));
  EXPECT_NEAR(probe_of(sc).pose().insertion, p0.insertion + 0.017, 1e-12);
  EXPECT_EQ(run.applier().refused(), 0);
}

TEST(ProbeSource, ADisconnectHoldsTheProbeAndSaysSo) {
  Scene sc = test::make_live_scene();
  SyntheticDevice dev;
  ProbeSource src(sc, dev);
  LockstepRunner run(*sc.sim);
  run.add_source(&src);
  ASSERT_TRUE(run.step());
  dev.st.position.z() = 0.004;
  ASSERT_TRUE(run.advance_to(30));
  dev.st.connected = false;
  dev.st.position.z() = 0.05;  // whatever it says now is ignored
  ASSERT_TRUE(run.advance_to(60));
  const double held = probe_of(sc).pose().insertion;
  ASSERT_TRUE(run.advance_to(120));
  EXPECT_EQ(probe_of(sc).pose().insertion, held);
  EXPECT_TRUE(src.disconnected());
  EXPECT_NE(src.status().find("disconnected at t="), std::string::npos) << src.status();
  // back: re-referenced where the device is now, no jump
  dev.st.connected = true;
  ASSERT_TRUE(run.advance_to(160));
  EXPECT_FALSE(src.disconnected());
  EXPECT_EQ(probe_of(sc).pose().insertion, held);
}

TEST(ProbeSource, MouseKeyboardArrowsTiltAndYaw) {
  MouseKeyboardDevice m(1e-4, 0.01, 0.2);
  DeviceState st;
  m.poll(0.0, st);
  m.key(MouseKeyboardDevice::Up, true);
  m.key(MouseKeyboardDevice::Left, true);
  m.poll(0.5, st);
  EXPECT_NEAR(st.rotation.x(), 0.1, 1e-12);
  EXPECT_NEAR(st.rotation.y(), -0.1, 1e-12);
  m.key(MouseKeyboardDevice::Up, false);
  m.key(MouseKeyboardDevice::Left, false);
  m.poll(1.0, st);
  EXPECT_NEAR(st.rotation.x(), 0.1, 1e-12);
}

}  // namespace
}  // namespace ps::haptics
