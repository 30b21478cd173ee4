// The haptic force loop (haptics/haptic_loop.h) with the simulated hand: pressed against tissue
// and released, the rendered force gives the hand no energy over 10 s of simulated time, at
// every physics tick rate tried (1 kHz, the rate every shipped scene uses, and 500 / 250 Hz with
// the device loop kept at 1 kHz); the force is clamped; the hand comes to rest.
#include "haptics/haptic_loop.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "engine/scenario/parse_yaml.h"
#include "haptics/simulated_hand.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps::haptics {
namespace {

Scene block_scene(int dt_ms) {
  test::BlockOptions o;
  std::string y = test::block_yaml(o, test::vertical_needle("n", 0.3, 0.2, "[[0, 0]]"));
  const std::string from = "time: {dt_ms: 1, substeps: 1, duration_s: 1}";
  y.replace(y.find(from), from.size(),
            "time: {dt_ms: " + std::to_string(dt_ms) + ", substeps: " + std::to_string(dt_ms) + ", duration_s: 10}");
  return build_scene(parse_scenario_text(y, "block.yaml"));
}

// press 9 mm (the tip starts 1 mm above the block) over 1.5 s, hold, pull back out, rest
double press_and_release(double t) {
  auto ramp = [](double a, double b, double t0, double t1, double t) {
    const double s = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    return a + (b - a) * s;
  };
  if (t < 4.0) return ramp(0.0, 0.009, 0.5, 2.0, t);
  return ramp(0.009, -0.004, 4.0, 5.5, t);
}

struct Result {
  double max_work = 0, final_work = 0, max_force = 0, rest_speed = 0;
  HapticStats stats;
};

Result run(int dt_ms, bool pc) {
  Scene sc = block_scene(dt_ms);
  HapticParams hp;
  hp.passivity_controller = pc;
  HapticRenderer r(hp);
  HapticCoupler coupler(sc, r, 0);
  SimulatedHand hand(press_and_release);
  LockstepRunner run(*sc.sim);
  run.add_source(&coupler);
  Result res;
  for (int s = 1; s <= 100; ++s) {  // 10 s in 0.1 s pieces, watching the energy as it goes
    EXPECT_TRUE(run_haptic_lockstep(run, coupler, r, hand, 0.1 * s)) << sc.sim->state().fault.describe(*sc.model);
    res.max_work = std::max(res.max_work, hand.work_in());
  }
  res.final_work = hand.work_in();
  res.stats = r.stats();
  res.rest_speed = std::abs(hand.velocity());
  return res;
}

TEST(HapticLoop, PressedAndReleasedGainsNoEnergyAtEveryTickRate) {
  for (int dt_ms : {1, 2, 4}) {
    const Result with = run(dt_ms, true);
    // the rendering alone, without the passivity controller, at the slowest physics rate (for
    // the report: how much the controller has to do at all)
    const Result raw = dt_ms == 4 ? run(dt_ms, false) : Result{};
    std::printf("physics %4d Hz, device 1000 Hz: max energy given to the hand %.3g J (final %.3g J), max force %.2f N, clamped %lld, "
                "controller acted %lld of %lld steps absorbing %.3g J; without the controller (250 Hz only): max %.3g J\n",
                1000 / dt_ms, with.max_work, with.final_work, with.stats.max_force, static_cast<long long>(with.stats.clamped),
                static_cast<long long>(with.stats.pc_steps), static_cast<long long>(with.stats.steps), with.stats.pc_absorbed,
                raw.max_work);
    EXPECT_EQ(with.stats.steps, 10000) << dt_ms;       // the device loop ran at 1 kHz throughout
    EXPECT_GT(with.stats.max_force, 0.3) << dt_ms;      // the tissue was really pressed
    EXPECT_LE(with.stats.max_force, HapticParams{}.max_force + 1e-9);
    // passive: the hand never got energy out of the simulation (1 uJ: the hand's trapezoid
    // integration against the loop's encoder velocity)
    EXPECT_LE(with.max_work, 1e-6) << dt_ms;
    EXPECT_LE(with.final_work, 0.0) << dt_ms;
    EXPECT_LT(with.rest_speed, 1e-3) << dt_ms;          // at rest after the release
  }
}

TEST(HapticLoop, ForceIsClampedAgainstAnAbsurdPush) {
  HapticParams hp;
  hp.max_force = 2.0;
  HapticRenderer r(hp);
  r.publish(LocalContact{0.0, 1.5, 3000.0, 0});
  double f = 0;
  for (int i = 0; i < 10; ++i) f = r.step(0.05 * i, 1e-3);  // a 50 m/s shove 50 mm into stiff tissue
  EXPECT_LE(std::abs(f), 2.0 + 1e-12);
  EXPECT_GT(r.stats().clamped, 0);
}

}  // namespace
}  // namespace ps::haptics
