#include "igtl/tracked_device.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace ps::igtl {
namespace {

TEST(IgtlTrackedDevice, AtItsReferenceUntilAPoseArrives) {
  TrackedDevice d("test");
  haptics::DeviceState s;
  ASSERT_TRUE(d.poll(0.0, s));
  EXPECT_TRUE(s.connected);
  EXPECT_EQ(s.position, Vec3::Zero());
  EXPECT_EQ(s.rotation, Vec3::Zero());
}

TEST(IgtlTrackedDevice, ReportsMotionInTheToolsFrameAtTheFirstPose) {
  TrackedDevice d("test");
  // the tool's z axis along the tracker's x: pushing it 5 mm along its own axis is device z
  const Mat3 r0 = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()).toRotationMatrix();
  const Vec3 p0(0.10, 0.02, -0.30);
  d.set_pose(r0, p0);
  d.set_pose(r0, p0 + 0.005 * r0.col(2));
  haptics::DeviceState s;
  ASSERT_TRUE(d.poll(0.0, s));
  EXPECT_NEAR(s.position.z(), 0.005, 1e-12);
  EXPECT_NEAR(s.position.x(), 0.0, 1e-12);
  EXPECT_NEAR(s.position.y(), 0.0, 1e-12);
  // then a 10 degree roll about its own axis: rotation z
  d.set_pose(r0 * Eigen::AngleAxisd(10 * M_PI / 180, Vec3::UnitZ()).toRotationMatrix(), p0);
  ASSERT_TRUE(d.poll(0.0, s));
  EXPECT_NEAR(s.rotation.z(), 10 * M_PI / 180, 1e-9);
  EXPECT_NEAR(s.rotation.x(), 0.0, 1e-9);
  EXPECT_EQ(d.poses_received(), 3);
}

TEST(IgtlTrackedDevice, IgnoresAReflection) {
  TrackedDevice d("test");
  d.set_pose(Mat3(Vec3(-1, 1, 1).asDiagonal()), Vec3(1, 2, 3));
  EXPECT_EQ(d.poses_received(), 0);
}

}  // namespace
}  // namespace ps::igtl
