// The cutting force solved with the needle's velocity (engine/tools/needle/needle_motion.cpp,
// implicit_cutting_force): the returned force is the root of u + beta C(u) = u0 on every branch
// of the gate's ramp, and it does not decrease as the needle is pushed harder.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/tools/needle/needle_internal.h"

namespace ps {
namespace {

// The gate as move_needle reads it after the substep: the force at axial speed u [m/s].
double gate(double c_full, double u, double v_cut, double a, double v_ramp) {
  return c_full * std::clamp(((1.0 - a) * v_cut + a * u) / v_ramp, 0.0, 1.0);
}

TEST(NeedleMotion, CuttingForceIsTheRootOfTheImplicitGateOnEveryBranch) {
  // the biopsy prostate's gate (1.5 N over 1 mm/s) on a 10 g needle at a 0.67 ms substep:
  // beta = h / (m + h c + h^2 k) with c = 20 N s/m, k = 2000 N/m
  const double h = 2e-3 / 3, c_full = 1.5, v_ramp = 1e-3, a = h / kCutFilterTime;
  const double beta = h / (0.010 + h * 20.0 + h * h * 2000.0);
  int on_ramp = 0, off = 0, full = 0;
  for (double v_cut : {-2e-3, 0.0, 0.4e-3, 3e-3})
    for (double u0 = -0.05; u0 <= 0.1; u0 += 1e-4) {
      const double C = implicit_cutting_force(c_full, u0, beta, v_cut, a, v_ramp);
      ASSERT_GE(C, 0.0);
      ASSERT_LE(C, c_full);
      const double u = u0 - beta * C;  // the needle's axial speed with that force
      EXPECT_NEAR(C, gate(c_full, u, v_cut, a, v_ramp), 1e-9 * c_full) << "v_cut " << v_cut << " u0 " << u0;
      on_ramp += C > 0.0 && C < c_full;
      off += C == 0.0;
      full += C == c_full;
    }
  EXPECT_GT(on_ramp, 10);
  EXPECT_GT(off, 10);
  EXPECT_GT(full, 10);
}

TEST(NeedleMotion, CuttingForceGrowsWithThePushAndStaysWithinItsLimit) {
  const double h = 1e-3, c_full = 0.5, v_ramp = 1e-3, a = h / kCutFilterTime, beta = h / 0.032;
  double last = -1.0;
  for (double u0 = -0.01; u0 <= 0.05; u0 += 1e-5) {
    const double C = implicit_cutting_force(c_full, u0, beta, 0.2e-3, a, v_ramp);
    EXPECT_GE(C, last - 1e-15);
    last = C;
  }
  EXPECT_EQ(last, c_full);
  EXPECT_EQ(0.0, implicit_cutting_force(0.0, 1.0, beta, 1.0, a, v_ramp)) << "no tissue ahead: no cutting";
  // beta = 0 (no feedback) is the explicit gate on the free speed
  EXPECT_NEAR(implicit_cutting_force(c_full, 0.5e-3, 0.0, 0.0, 1.0, v_ramp), 0.25, 1e-12);
}

}  // namespace
}  // namespace ps
