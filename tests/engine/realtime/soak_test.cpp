// Tests for engine/realtime/soak.cpp: the looping script player and the CI-sized soak (the
// one-hour soak of the default scenes is the benchmark `prostatesim stress --cases soak --soak
// 3600`, docs/robustness.md). The small live scene (tests/engine/realtime/live_scene.h) runs a
// 0.2 s script that moves the probe, drives a needle in, fires its gun, fills and empties the
// bladder and puts everything back, three cycles under the watchdog.
#include "engine/realtime/soak.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/realtime/lockstep.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"
#include "tests/engine/realtime/live_scene.h"

namespace ps {
namespace {

const char* kLoopScript = R"(scenario: live_box
duration_s: 0.2
timeline:
  - {t: 0.0, probe: {insertion_mm: 52}, over_s: 0.05}
  - {t: 0.0, needle: gun, depth_mm: 0}
  - {t: 0.02, fill_rate: bladder, ml_s: 50}
  - {t: 0.08, needle: gun, depth_mm: 18}
  - {t: 0.09, fire: gun}
  - {t: 0.10, fill_rate: bladder, ml_s: -50}
  - {t: 0.12, needle: gun, depth_mm: 18}
  - {t: 0.16, probe: {insertion_mm: 50}, over_s: 0.03}
  - {t: 0.18, needle: gun, depth_mm: 0}
  - {t: 0.18, fill_rate: bladder, ml_s: 0}
)";

struct TickLog final : CommandObserver {
  std::vector<int64_t> ticks;
  void applied(const Command& c) override { ticks.push_back(c.tick); }
};

TEST(LoopingPlayer, ReplaysTheScriptEveryPeriodInOrder) {
  Scene sc = test::make_live_scene();
  const Script s = parse_script_text(kLoopScript, "loop.yaml");
  const std::vector<Command> cmds = script_commands(s, sc);
  ASSERT_FALSE(cmds.empty());
  LoopingPlayer player(cmds, 200);
  EXPECT_EQ(player.period(), 200);
  LockstepRunner run(*sc.sim);
  TickLog log;
  run.applier().set_observer(&log);
  run.add_source(&player);
  ASSERT_TRUE(run.advance_to(600));
  ASSERT_EQ(log.ticks.size(), 3 * cmds.size());
  for (size_t c = 0; c < 3; ++c)
    for (size_t k = 0; k < cmds.size(); ++k) EXPECT_EQ(log.ticks[c * cmds.size() + k], cmds[k].tick + 200 * static_cast<int64_t>(c));
  EXPECT_EQ(run.applier().refused(), 0);
}

TEST(LoopingPlayer, StretchesAPeriodShorterThanTheScript) {
  std::vector<Command> cmds(2);
  cmds[0].tick = 0;
  cmds[1].tick = 9;
  EXPECT_EQ(LoopingPlayer(cmds, 5).period(), 10);  // the next cycle starts after the last command
  EXPECT_EQ(LoopingPlayer({}, 0).period(), 1);
}

TEST(Soak, CiSizedSoakOfTheLiveSceneHoldsAndReportsItsDrift) {
  const Script s = parse_script_text(kLoopScript, "loop.yaml");
  SoakOptions opt;
  opt.duration = 0.6;  // three cycles
  Scene sc = test::make_live_scene();
  const SoakReport r = run_soak(sc, &s, opt);
  ASSERT_TRUE(r.held) << r.fault;
  EXPECT_FALSE(r.timeout);
  EXPECT_EQ(r.ticks, 600);
  EXPECT_EQ(r.period_ticks, 200);
  EXPECT_EQ(r.cycles, 3);
  EXPECT_EQ(r.refused, 0);
  EXPECT_EQ(r.applied, 3 * static_cast<int64_t>(script_commands(s, sc).size()));
  EXPECT_EQ(r.peaks.checks, 600);
  // the instruments moved the tissue: the peaks are real measurements, within the watchdog's limits
  EXPECT_GT(r.peaks.max_speed, 0.0);
  EXPECT_LT(r.peaks.max_speed, opt.limits.max_speed);
  EXPECT_GT(r.peaks.max_kinetic, 0.0);
  EXPECT_LT(r.peaks.max_kinetic, r.kinetic_limit);
  EXPECT_GT(r.peaks.max_displacement, 0.0);
  EXPECT_GT(r.peaks.min_margin, 0.0);
  EXPECT_LE(r.peaks.max_volume_drift, opt.limits.volume_drift);
  EXPECT_GE(r.peaks.worst_surface, 0);
  ASSERT_FALSE(r.end_volume_drift.empty());
  const std::string fig = soak_figures(r, *sc.model);
  EXPECT_NE(fig.find("3 cycles"), std::string::npos) << fig;
  EXPECT_NE(fig.find("cycle drift (end of cycle 3 vs end of cycle 1)"), std::string::npos) << fig;

  // The cycle drift is the distance between the ends of cycle 1 and cycle 3: rerun one cycle
  // (deterministic: the same bits) and compare.
  Scene one = test::make_live_scene();
  opt.duration = 0.2;
  const SoakReport r1 = run_soak(one, &s, opt);
  ASSERT_TRUE(r1.held) << r1.fault;
  EXPECT_EQ(r1.cycles, 1);
  double mx = 0.0;
  for (size_t p = 0; p < one.sim->state().x.size(); ++p)
    mx = std::max(mx, (sc.sim->state().x[p] - one.sim->state().x[p]).norm());
  EXPECT_EQ(r.cycle_drift_max, mx);
  std::printf("live_box soak: %s\n", fig.c_str());
}

TEST(Soak, AWatchdogFindingStopsTheSoakNamingTickAndParticle) {
  const Script s = parse_script_text(kLoopScript, "loop.yaml");
  SoakOptions opt;
  opt.duration = 0.6;
  opt.limits.max_speed = 1e-3;  // [m/s] the probe moves the tissue faster than this
  Scene sc = test::make_live_scene();
  const SoakReport r = run_soak(sc, &s, opt);
  EXPECT_FALSE(r.held);
  EXPECT_LT(r.ticks, 600);
  EXPECT_NE(r.fault.find("watchdog: energy growth"), std::string::npos) << r.fault;
  EXPECT_NE(r.fault.find("particle"), std::string::npos) << r.fault;
  EXPECT_NE(r.fault.find("tick " + std::to_string(r.ticks - 1) + ":"), std::string::npos) << r.fault;
}

TEST(Soak, TheWallBudgetEndsItAsATimeout) {
  SoakOptions opt;
  opt.duration = 3600.0;
  opt.budget_s = 1e-6;  // [s] runs out at the first look at the clock
  Scene sc = test::make_live_scene();
  const SoakReport r = run_soak(sc, nullptr, opt);
  EXPECT_TRUE(r.held);
  EXPECT_TRUE(r.timeout);
  EXPECT_EQ(r.ticks, 64);
  EXPECT_EQ(r.period_ticks, 1000);  // no script: drift compared every opt.period = 1 s
}

TEST(Soak, ASoakStoppedByItsBudgetLeavesACheckpointToGoOnFrom) {
  // the budget ends the first sitting at tick 64; a second sitting goes on from its checkpoint
  // to tick 128 and ends where one sitting of 128 ticks ends
  SoakOptions opt;
  opt.duration = 0.128;  // [s]
  opt.budget_s = 1e-6;   // [s]
  std::vector<SoakCheckpoint> taken;
  opt.checkpoint = [&](const SoakCheckpoint& c) { taken.push_back(c); };
  Scene first = test::make_live_scene();
  const SoakReport r1 = run_soak(first, nullptr, opt);
  ASSERT_TRUE(r1.timeout);
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].state.tick, 64);
  SoakOptions rest;
  rest.duration = opt.duration;
  Scene second = test::make_live_scene();
  const SoakReport r2 = run_soak(second, nullptr, rest, {}, &taken[0]);
  EXPECT_TRUE(r2.held);
  EXPECT_FALSE(r2.timeout);
  EXPECT_EQ(r2.ticks, 128);
  Scene straight = test::make_live_scene();
  const SoakReport r3 = run_soak(straight, nullptr, rest);
  EXPECT_EQ(second.sim->hash(), straight.sim->hash()) << "bit-identical to one sitting";
  EXPECT_EQ(r2.peaks.max_speed, r3.peaks.max_speed);
  EXPECT_EQ(r2.peaks.checks, r3.peaks.checks);
}

// The paper's literal redistribution with a raw stiff k_e grows an oscillation at any substep
// (tests/app/cli_test.cpp, BlowUpExits3NamingParticleAndTime). With the watchdog's speed limit out of
// the way, the growth shows first as the end-of-cycle kinetic energy: a finding naming the cycle
// and the fastest particle, before the step's own fault or the energy limit.
TEST(Soak, AnOscillationGrowingFromCycleToCycleIsAFindingBelowTheWatchdogsLimits) {
  const ScenarioSpec spec = parse_scenario_text(
      "name: ring\nsolver: {redistribution: linear}\ntime: {dt_ms: 1, duration_s: 1}\n"
      "materials:\n  soft: {k_e_n_m: 2.0e4, damping_1_s: 0}\ncomponents:\n"
      "  - {name: cube, material: soft, spacing_mm: 10, box: {min_mm: [0,0,0], max_mm: [40,40,40]}}\n"
      "constraints:\n  - fix: {component: cube, region: {box: {min_mm: [-1,-1,-1], max_mm: [41,41,0.5]}}}\n",
      "ring.yaml");
  SoakOptions opt;
  opt.duration = 5.0;  // [s]
  opt.period = 0.05;   // [s] a cycle without a script
  opt.limits.max_speed = 1e3;  // [m/s]
  Scene sc = build_scene(spec);
  const SoakReport r = run_soak(sc, nullptr, opt);
  std::printf("ring: %s\nfigures: %s\n", r.fault.c_str(), soak_figures(r, *sc.model).c_str());
  EXPECT_FALSE(r.held);
  EXPECT_NE(r.fault.find("self-excited oscillation"), std::string::npos) << r.fault;
  EXPECT_NE(r.fault.find("particle"), std::string::npos) << r.fault;
  EXPECT_EQ(r.ring_base_cycle, 1);  // no scenario scripts: the first cycle end is the reference
  EXPECT_GT(r.cycle_end_kinetic_last, opt.ring_factor * r.ring_base_kinetic + opt.ring_floor_j);
  // without the detector the same run goes on past that tick
  SoakOptions off = opt;
  off.ring_factor = 0.0;
  Scene again = build_scene(spec);
  const SoakReport r0 = run_soak(again, nullptr, off);
  std::printf("without: held %d at tick %lld: %s\n", r0.held, static_cast<long long>(r0.ticks), r0.fault.c_str());
  EXPECT_GT(r0.ticks, r.ticks);
}

// A scene's own scenario script is not a self-excitation: the reference is the first cycle end
// after it. Here a needle driven in at 30 mm/s for 0.6 s, through a soft block with damping:
// the kinetic energy at the end of cycle 3 (needle still cutting) is far above that at the end of
// cycle 1 (just touching), and the scene comes to rest once the needle stops.
TEST(Soak, TheScenesOwnScriptIsNotASelfExcitation) {
  const ScenarioSpec spec = parse_scenario_text(
      "name: own_script\ntime: {dt_ms: 1, duration_s: 1}\n"
      "materials:\n  soft: {model: tet, young_kpa: 10, density_kg_m3: 1000, damping_1_s: 40, k_c_n: 0.3, k_f_n: 0.02}\n"
      "components:\n  - {name: block, material: soft, spacing_mm: 5, box: {min_mm: [-20,-20,-40], max_mm: [20,20,0]}}\n"
      "constraints:\n  - fix: {component: block, region: {box: {min_mm: [-21,-21,-41], max_mm: [21,21,-39.5]}}}\n"
      "needles:\n  puncture_n: {block: 0.5}\n  instruments:\n"
      "    - {name: n, gauge: 18, length_mm: 100, start_mm: [0.3, 0.2, 5], direction: [0, 0, -1], script: [[0, 0], [0.6, 23]]}\n",
      "own_script.yaml");
  EXPECT_DOUBLE_EQ(scripted_motion_end(spec), 0.6);
  SoakOptions opt;
  opt.duration = 1.5;  // [s]
  opt.period = 0.1;    // [s]
  Scene sc = build_scene(spec);
  const SoakReport r = run_soak(sc, nullptr, opt);
  EXPECT_TRUE(r.held) << r.fault;
  EXPECT_EQ(r.ring_base_cycle, 6);  // t = 0.6 s
  EXPECT_EQ(r.cycles, 15);
  // what a reference at the first cycle end would have called growth
  std::printf("own script: cycle 1 end %.3g J, reference (cycle %lld) %.3g J, last %.3g J; peak %.3g m/s\n",
              r.cycle_end_kinetic_first, static_cast<long long>(r.ring_base_cycle), r.ring_base_kinetic, r.cycle_end_kinetic_last,
              r.peaks.max_speed);
  EXPECT_GT(r.ring_base_kinetic, opt.ring_factor * r.cycle_end_kinetic_first + opt.ring_floor_j);
  EXPECT_LE(r.cycle_end_kinetic_last, r.ring_base_kinetic);
}

}  // namespace
}  // namespace ps
