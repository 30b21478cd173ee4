#include "app/gui/tip_target.h"

#include <gtest/gtest.h>

namespace ps::gui {
namespace {

// The brachytherapy script's `posterior` needle: in to 75 mm along its line (its target), then
// drawn back to 35 mm while the seeds drop. The live figure read the tip's distance from the
// target all along, ~34 mm once withdrawn; it now holds the error at the deepest point.
TEST(TipTarget, HoldsTheErrorAtTheDeepestPointWhenTheNeedleIsDrawnBack) {
  TipTargetHold h;
  EXPECT_FALSE(h.measured());
  EXPECT_DOUBLE_EQ(h.update(0.010, 30.0), 30.0);   // advancing: follows the tip
  EXPECT_DOUBLE_EQ(h.update(0.025, 12.0), 12.0);
  EXPECT_DOUBLE_EQ(h.update(0.040, 0.8), 0.8);     // deepest
  EXPECT_FALSE(h.held(0.040));
  EXPECT_DOUBLE_EQ(h.update(0.039, 1.5), 0.8);     // recoil within 2 mm: not yet held, same value
  EXPECT_FALSE(h.held(0.039));
  EXPECT_DOUBLE_EQ(h.update(0.020, 20.5), 0.8);    // withdrawn 20 mm: still the deepest's error
  EXPECT_TRUE(h.held(0.020));
  EXPECT_DOUBLE_EQ(h.update(0.041, 0.6), 0.6);     // pushed deeper again: follows
}

}  // namespace
}  // namespace ps::gui
