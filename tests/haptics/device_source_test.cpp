// Devices mapped to instrument commands (haptics/device_source.h): the mapped device drives the
// needle, buttons fire on the press; a device that disconnects mid-session leaves the needle
// where it was (no further motion, no jump) and says so; the mouse+keyboard device is read
// lock-free; a SpaceMouse without spacenavd gives a clear message.
#include "haptics/device_source.h"

#include <gtest/gtest.h>

#include "engine/realtime/lockstep.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/tools/needle/needle.h"
#include "haptics/mouse_keyboard.h"
#include "haptics/spacemouse.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps::haptics {
namespace {

class FakeDevice final : public Device {
 public:
  const char* name() const override { return "fake"; }
  bool poll(double, DeviceState& out) override {
    out = st;
    return st.connected;
  }
  DeviceState st;
};

TEST(DeviceSource, DrivesTheNeedleAndADisconnectLeavesItWhereItWas) {
  test::BlockOptions o;
  Scene sc = build_scene(parse_scenario_text(test::block_yaml(o, test::vertical_needle("n", 0.3, 0.2, "[[0, 0]]")), "block.yaml"));
  FakeDevice dev;
  DeviceSource src(sc, dev);
  LockstepRunner run(*sc.sim);
  run.add_source(&src);
  const auto& needle = *sc.tools.as<NeedleTool>();
  for (int k = 1; k <= 200; ++k) {   // push 10 mm over 0.2 s
    dev.st.position.z() = 0.010 * k / 200.0;
    ASSERT_TRUE(run.step());
  }
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(run.step());
  const double depth_before = needle.readout(0).plan_depth;
  EXPECT_NEAR(depth_before, 0.010, 1.5e-3);  // followed the device (coupling lag, tissue load)
  EXPECT_EQ(src.status(), "fake: ok");
  dev.st.connected = false;                   // unplugged
  dev.st.position.z() = 0.030;                // whatever it reads now is ignored
  for (int k = 0; k < 300; ++k) ASSERT_TRUE(run.step());
  EXPECT_TRUE(src.disconnected());
  EXPECT_NE(src.status().find("disconnected"), std::string::npos) << src.status();
  EXPECT_NE(src.status().find("held where they were"), std::string::npos) << src.status();
  EXPECT_NEAR(needle.readout(0).plan_depth, depth_before, 5e-4);
  // reconnecting resumes from where the needle is: no jump to the device's new reading
  dev.st.connected = true;
  for (int k = 0; k < 50; ++k) ASSERT_TRUE(run.step());
  EXPECT_FALSE(src.disconnected());
  EXPECT_NEAR(needle.readout(0).plan_depth, depth_before, 5e-4);
  EXPECT_EQ(run.applier().refused(), 0);
}

TEST(MouseKeyboard, DragAndKeysMapToTravelAndButtons) {
  MouseKeyboardDevice d(1e-4, 0.01);
  DeviceState st;
  d.drag(-50);  // 50 px up
  ASSERT_TRUE(d.poll(0.0, st));
  EXPECT_NEAR(st.position.z(), 0.005, 1e-12);
  d.key(MouseKeyboardDevice::W, true);
  d.poll(0.5, st);
  d.key(MouseKeyboardDevice::W, false);
  d.poll(1.0, st);  // W held for 0.5 s at 10 mm/s
  EXPECT_NEAR(st.position.z(), 0.010, 1e-12);
  d.key(MouseKeyboardDevice::Space, true);
  d.poll(1.0, st);
  EXPECT_TRUE(st.buttons & kButtonFire);
  d.key(MouseKeyboardDevice::Space, false);
  d.poll(1.0, st);
  EXPECT_FALSE(st.buttons & kButtonFire);
  d.set_connected(false);
  EXPECT_FALSE(d.poll(1.0, st));
}

TEST(SpaceMouse, WithoutTheDaemonSaysSoAndReadsDisconnected) {
  SpaceMouseDevice sm;
  std::string why;
  if (sm.open(why)) GTEST_SKIP() << "a spacenavd is running here";
  EXPECT_NE(why.find("spacenavd"), std::string::npos) << why;
  EXPECT_NE(why.find("falling back"), std::string::npos) << why;
  DeviceState st;
  EXPECT_FALSE(sm.poll(0.0, st));
  EXPECT_FALSE(st.connected);
}

}  // namespace
}  // namespace ps::haptics
