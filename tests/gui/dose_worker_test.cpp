// The trainee window's dose worker (app/gui/dose_worker.cpp): from a submitted snapshot with seeds
// it hands back the indices, a copy of the dose grid (the TRUS panel's isodose lines) and the
// prescription isodose surface (the 3D view), off the UI thread; no seed, no surface.
#include "app/gui/dose_worker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "engine/realtime/lockstep.h"
#include "engine/sim/scene.h"
#include "tests/gui/worker_wait.h"

namespace ps::gui {
namespace {

TEST(DoseWorker, SeedsGiveIndicesAGridAndThePrescriptionSurface) {
  Scene scene = load_scene(PROSTATESIM_SOURCE_DIR "/config/brachytherapy.yaml");
  LockstepRunner run(*scene.sim);
  Snapshot snap = run.snapshot();
  DoseWorker w(scene);
  const DoseFrame none = test::next_frame<DoseFrame>(w, snap);
  ASSERT_TRUE(none.ready);
  EXPECT_EQ(none.seeds, 0);
  ASSERT_TRUE(none.surface);
  EXPECT_TRUE(none.surface->faces.empty());
  // twelve 0.5 U seeds on a 16 mm ring around the gland's centre (the frame's origin), along +z
  for (int k = 0; k < 12; ++k) {
    const double a = 2.0 * 3.141592653589793 * k / 12;
    const Vec3 c(0.008 * std::cos(a), 0.008 * std::sin(a), 0.004 * (k % 3 - 1));
    snap.draw.capsules.push_back({c - Vec3(0, 0, 0.00225), c + Vec3(0, 0, 0.00225), 0.0004, Rgba{}, DrawRole::Seed});
  }
  snap.tick += 100;
  const DoseFrame f = test::next_frame<DoseFrame>(w, snap);
  ASSERT_TRUE(f.ready);
  EXPECT_EQ(f.seeds, 12);
  ASSERT_TRUE(f.field && f.surface);
  EXPECT_GT(f.indices.prostate_v100, 0.1);  // twelve seeds cover a small part of a 29.5 cc gland (13.6 %)
  // the surface surrounds the ring at the prescription: its vertices lie on the edges of the 2 mm
  // cells the views take, so on the 1 mm grid they are at 145 Gy to within that edge's linear
  // interpolation: 2 % for the median vertex (measured 2.0 %), up to 33 % beside a seed's axis
  // where the 6711's anisotropy dips (the surface's accuracy: tests/engine/dosimetry/isodose_test.cpp)
  ASSERT_GT(f.surface->faces.size(), 500u);
  std::vector<double> dev;
  double far = 0.0;
  for (const Vec3& v : f.surface->vertices_mm) {
    dev.push_back(std::abs(f.field->at(v) / 145.0 - 1.0));
    far = std::max(far, v.norm());
  }
  std::sort(dev.begin(), dev.end());
  const double median = dev[dev.size() / 2], worst = dev.back();
  std::printf("surface vertices: |D / 145 Gy - 1| median %.4f, worst %.4f; farthest %.1f mm\n", median, worst, far);
  EXPECT_LT(median, 0.03);
  EXPECT_LT(far, 25.0) << "the 145 Gy surface of twelve seeds stays within ~25 mm of the ring's centre";
  EXPECT_GE(f.field->at(Vec3(8, 0, 0)), 145.0) << "beside a seed: inside the prescription";
  std::printf("dose worker: %d seeds, update %.1f ms + isodose %.1f ms, %zu triangles\n", f.seeds, f.ms, f.iso_ms,
              f.surface->faces.size());
}

}  // namespace
}  // namespace ps::gui
