// Scripted needle sessions whose answer is known: on target ~0 mm, 5 mm off ~5 mm, a withdrawal
// and push again is one re-insertion, a needle through the urethra line hits it, a biopsy core in
// the tumour is a lesion hit; the observer does not allocate once built.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/metrics/score.h"
#include "engine/metrics/session_metrics.h"
#include "engine/util/error.h"
#include "tests/engine/counting_allocator.h"
#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps {
namespace {

SessionReport run_session(test::NeedleScene& s, double seconds, const MetricsOptions& opt = {}) {
  SessionMetrics metrics(*s.model, *s.tool, opt);
  const int ticks = static_cast<int>(std::lround(seconds / s.model->dt));
  for (int i = 0; i < ticks; ++i) {
    EXPECT_TRUE(s.sim->tick());
    metrics.observe(*s.tool, s.sim->state());
  }
  return metrics.finish(*s.tool, s.sim->state());
}

// Vertical needle at (0, 0) from 1 mm above the block to 13 mm deep (tip at z = -12 mm).
std::string aimed_block(const std::string& target_mm, const std::string& script = "[[0, 0], [0.5, 13]]") {
  test::BlockOptions o;
  return test::block_yaml(o, test::vertical_needle("n", 0, 0, script, "      target_mm: " + target_mm + "\n"));
}

TEST(SessionMetrics, NeedleScriptedOntoItsTargetScoresAboutZero) {
  auto s = test::make_needle_scene(aimed_block("[0, 0, -12]"));
  const SessionReport r = run_session(s, 0.8);
  ASSERT_EQ(r.needles.size(), 1u);
  const NeedleMetrics& n = r.needles[0];
  ASSERT_TRUE(n.scored);
  EXPECT_EQ(n.measured_at, "deepest");
  std::printf("on target: error %.3f mm (lateral %.3f, depth %.3f), target moved %.3f mm\n", 1e3 * n.error, 1e3 * n.lateral_error,
              1e3 * n.depth_error, 1e3 * (n.target_now - n.target_rest).norm());
  EXPECT_LT(n.error, 1.0e-3);
  EXPECT_EQ(n.punctures, 1);
  EXPECT_EQ(n.reinsertions, 0);
  EXPECT_TRUE(n.structures_hit.empty());
  EXPECT_GT(n.peak_force, 0.0);
  EXPECT_GT(n.mean_force, 0.0);
  EXPECT_LE(n.mean_force, n.peak_force);
  EXPECT_GT(n.insertion_time, 0.3);   // contact near 1 mm / 26 mm/s, deepest at or after 0.5 s
  EXPECT_LT(n.insertion_time, 0.8);
  const Score sc = score_session(r);
  EXPECT_GT(sc.value, 95.0);
}

TEST(SessionMetrics, NeedleAimedFiveMillimetresOffScoresAboutFive) {
  auto s = test::make_needle_scene(aimed_block("[5, 0, -12]"));
  const SessionReport r = run_session(s, 0.8);
  const NeedleMetrics& n = r.needles[0];
  ASSERT_TRUE(n.scored);
  std::printf("5 mm off: error %.3f mm (lateral %.3f, depth %.3f)\n", 1e3 * n.error, 1e3 * n.lateral_error, 1e3 * n.depth_error);
  EXPECT_NEAR(n.error, 5e-3, 1.0e-3);
  EXPECT_NEAR(n.lateral_error, 5e-3, 1.0e-3);
  EXPECT_LT(std::abs(n.depth_error), 1.0e-3);
  const Score sc = score_session(r);
  EXPECT_NEAR(sc.value, 100.0 - 4.0 * 1e3 * r.mean_error, 1e-9);
  EXPECT_NEAR(han_scale_position(r.mean_error), 0.5, 0.15);  // 5 mm: half way from robot to freehand
}

TEST(SessionMetrics, TooShallowIsADepthError) {
  auto s = test::make_needle_scene(aimed_block("[0, 0, -17]"));
  const SessionReport r = run_session(s, 0.8);
  const NeedleMetrics& n = r.needles[0];
  std::printf("5 mm short: error %.3f mm (depth %.3f)\n", 1e3 * n.error, 1e3 * n.depth_error);
  EXPECT_NEAR(n.depth_error, -5e-3, 1.0e-3);
  EXPECT_LT(n.lateral_error, 1.0e-3);
}

TEST(SessionMetrics, WithdrawAndPushAgainIsOneReinsertion) {
  auto s = test::make_needle_scene(aimed_block("[0, 0, -12]", "[[0, 0], [0.3, 10], [0.5, 4], [0.8, 13]]"));
  const SessionReport r = run_session(s, 1.0);
  EXPECT_EQ(r.needles[0].reinsertions, 1);
  EXPECT_EQ(r.reinsertions, 1);
  const Score sc = score_session(r);
  bool found = false;
  for (const ScoreTerm& t : sc.terms)
    if (t.name == "reinsertion") { EXPECT_EQ(t.points, 3.0); found = true; }
  EXPECT_TRUE(found);
}

TEST(SessionMetrics, TargetOutsideEveryOrganIsRefused) {
  auto s = test::make_needle_scene(aimed_block("[0, 0, 30]"));
  try {
    SessionMetrics m(*s.model, *s.tool);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "needles.instruments[0].target_mm");
  }
}

TEST(SessionMetrics, NeedleThroughTheUrethraLineHitsIt) {
  test::BlockOptions o;
  auto s = test::make_needle_scene(test::block_yaml(
      o, test::vertical_needle("through", 0, 0, "[[0, 0], [0.5, 13]]") + test::vertical_needle("beside", 8, 0, "[[0, 0], [0.5, 13]]")));
  MetricsOptions opt;
  for (int k = -10; k <= 10; k += 2) opt.urethra.push_back(Vec3(0, 1e-3 * k, -8e-3));  // along y under "through"
  const SessionReport r = run_session(s, 0.8, opt);
  ASSERT_EQ(r.needles.size(), 2u);
  ASSERT_EQ(r.needles[0].structures_hit.size(), 1u);
  EXPECT_EQ(r.needles[0].structures_hit[0], "urethra");
  EXPECT_TRUE(r.needles[1].structures_hit.empty());
  EXPECT_EQ(r.structures_hit, 1);
}

TEST(SessionMetrics, BiopsyCoreInTheTumourIsALesionHit) {
  std::string y = test::biopsy_yaml();
  y += "      target_mm: [1.3, 0.9, -22]\n      planned_site: anywhere\n";
  auto s = test::make_needle_scene(y);
  const SessionReport r = run_session(s, 0.7);
  ASSERT_EQ(r.cores.size(), 1u);
  const CoreMetrics& c = r.cores[0];
  EXPECT_TRUE(c.taken);
  EXPECT_TRUE(c.lesion_hit);
  EXPECT_GT(c.lesion_length, 0.0);
  EXPECT_LE(c.lesion_length, c.notch_length);
  EXPECT_EQ(r.lesions_targeted, 1);
  EXPECT_EQ(r.lesions_missed, 0);
  EXPECT_EQ(r.needles[0].measured_at, "core");
  std::printf("core: notch centre %.2f mm from the target, lesion length %.1f mm\n", 1e3 * r.needles[0].error, 1e3 * c.lesion_length);
  // the scene has no prostate zones: the core has no site, so the planned site is not covered
  EXPECT_EQ(r.coverage, 0.0);
  ASSERT_EQ(r.cores_per_zone.size(), 1u);
  EXPECT_EQ(r.cores_per_zone[0].first, "outside the gland");
}

// The biopsy scene with its deep block renamed: whether a core in it is a lesion hit is the
// block's role, not its name.
std::string renamed_biopsy(const std::string& role) {
  std::string y = test::biopsy_yaml();
  for (size_t at; (at = y.find("tumour")) != std::string::npos;) y.replace(at, 6, "deep_block");
  y.replace(y.find("{name: deep_block, "), 19, "{name: deep_block, " + role);
  return y + "      target_mm: [1.3, 0.9, -22]\n      planned_site: anywhere\n";
}

TEST(SessionMetrics, ACoreIsALesionHitByTheRoleNotTheName) {
  auto lesion = test::make_needle_scene(renamed_biopsy("role: lesion, "));
  const SessionReport r = run_session(lesion, 0.7);
  ASSERT_EQ(r.cores.size(), 1u);
  EXPECT_TRUE(r.cores[0].lesion_hit);
  EXPECT_EQ(r.lesions_targeted, 1);
  auto plain = test::make_needle_scene(renamed_biopsy(""));
  const SessionReport q = run_session(plain, 0.7);
  ASSERT_EQ(q.cores.size(), 1u);
  EXPECT_FALSE(q.cores[0].lesion_hit);
  EXPECT_EQ(q.lesions_targeted, 0);
}

// A needle from the tissue block into a second block below it: that block's role decides which
// structure the needle hit (a name that reads "gland" does not make it the gland).
TEST(SessionMetrics, TheStructureHitIsTheComponentsRole) {
  auto hits = [](const std::string& role) {
    test::BlockOptions o;
    o.depth_mm = 16;
    o.walls = false;
    o.extra_components = "  - {name: gland_left_thing, " + role +
                         "material: tissue, spacing_mm: 4, box: {min_mm: [-12, -12, -40], max_mm: [12, 12, -20]}}\n";
    o.extra_puncture = ", gland_left_thing: 1.5";  // a wall the needle punctures: the event of the hit
    o.extra_constraints = "  - fix: {component: gland_left_thing, region: {box: {min_mm: [-100, -100, -41], max_mm: [100, 100, -39]}}}\n";
    std::string y = test::block_yaml(o, test::vertical_needle("n", 1.3, 0.9, "[[0, 0], [0.6, 30]]"));
    y.replace(y.find("constraints:\n"), 13, "links:\n  - {a: tissue, b: gland_left_thing, distance_mm: 5}\nconstraints:\n");
    auto s = test::make_needle_scene(y);
    const SessionReport r = run_session(s, 0.8);
    return r.needles.at(0).structures_hit;
  };
  EXPECT_EQ(hits("role: bladder, "), std::vector<std::string>{"bladder"});
  EXPECT_EQ(hits("role: rectum, "), std::vector<std::string>{"rectal wall"});
  EXPECT_TRUE(hits("").empty());  // by name: the gland, not a structure to avoid
}

TEST(SessionMetrics, SeedsAgainstTheirPlannedSitesCarriedByTheTissue) {
  test::BlockOptions o;
  auto s = test::make_needle_scene(
      test::block_yaml(o, test::vertical_needle("b", 1.3, 0.9, "[[0, 0], [0.8, 17], [1.0, 17], [1.8, 2]]", "      seeds_mm: [15, 11, 7]\n")));
  MetricsOptions opt;
  opt.gland = "tissue";
  const SessionReport r = run_session(s, 2.0, opt);
  ASSERT_EQ(r.seeds.size(), 3u);
  for (const SeedMetrics& sm : r.seeds) {
    EXPECT_TRUE(sm.deposited);
    EXPECT_FALSE(sm.outside_gland);
    EXPECT_LT(sm.error, 3e-3);
  }
  EXPECT_TRUE(r.gland_known);
  EXPECT_EQ(r.seeds_outside_gland, 0);
  std::printf("seeds: mean %.2f mm, max %.2f mm\n", 1e3 * r.seed_error_mean, 1e3 * r.seed_error_max);
  EXPECT_GE(r.seed_error_max, r.seed_error_mean);
}

TEST(SessionMetrics, ObservingDoesNotAllocate) {
  auto s = test::make_needle_scene(aimed_block("[0, 0, -12]", "[[0, 0], [0.3, 10], [0.5, 4], [0.8, 13]]"));
  MetricsOptions opt;
  for (int k = -10; k <= 10; k += 2) opt.urethra.push_back(Vec3(0, 1e-3 * k, -8e-3));
  SessionMetrics metrics(*s.model, *s.tool, opt);
  for (int i = 0; i < 20; ++i) {  // warm up
    ASSERT_TRUE(s.sim->tick());
    metrics.observe(*s.tool, s.sim->state());
  }
  long allocations = 0;
  for (int i = 0; i < 800; ++i) {
    ASSERT_TRUE(s.sim->tick());
    const long before = test::allocation_count();
    metrics.observe(*s.tool, s.sim->state());
    allocations += test::allocation_count() - before;
  }
  EXPECT_EQ(allocations, 0);
}

TEST(WindingNumber, InsideAndOutsideTheBlockSurface) {
  test::BlockOptions o;
  auto s = test::make_needle_scene(test::block_yaml(o, test::vertical_needle("n", 0, 0, "[[0, 0]]")));
  const Model& m = *s.model;
  const Surface& surf = m.surfaces[m.components[m.find_component("tissue")].surface];
  EXPECT_NEAR(winding_number(surf, m.rest_pos, Vec3(0, 0, -12e-3)), 1.0, 1e-6);
  EXPECT_NEAR(winding_number(surf, m.rest_pos, Vec3(0, 0, 10e-3)), 0.0, 1e-6);
  EXPECT_NEAR(winding_number(surf, m.rest_pos, Vec3(30e-3, 0, -12e-3)), 0.0, 1e-6);
}

}  // namespace
}  // namespace ps
