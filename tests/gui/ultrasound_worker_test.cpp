// The trainee window's ultrasound worker (app/gui/ultrasound_worker.cpp): it forms both planes
// off the UI thread from submitted snapshots, and its gain / depth / frequency knobs change the
// next image; settings out of range are refused naming the field, and change nothing.
#include "app/gui/ultrasound_worker.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "engine/realtime/lockstep.h"
#include "engine/sim/scene.h"
#include "engine/util/error.h"
#include "tests/gui/worker_wait.h"

namespace ps::gui {
namespace {

// mean gray of `v` over the pixels where `ref` is not black (in the field of view, not shadowed)
double mean_where_lit(const std::vector<uint8_t>& v, const std::vector<uint8_t>& ref) {
  double s = 0.0;
  int n = 0;
  for (size_t p = 0; p < v.size() && p < ref.size(); ++p)
    if (ref[p] > 0) s += v[p], ++n;
  return n ? s / n : 0.0;
}

TEST(UltrasoundWorker, KnobsChangeTheNextImageAndBadValuesAreRefused) {
  Scene scene = load_scene(PROSTATESIM_SOURCE_DIR "/config/biopsy.yaml");
  LockstepRunner run(*scene.sim);
  const Snapshot snap = run.snapshot();
  UltrasoundWorker w(scene, 128);
  const UsControls c0 = w.controls();
  EXPECT_EQ(c0.gain_db, 0.0);
  EXPECT_NEAR(c0.depth_m, 0.060, 1e-12);
  const UsFrame base = test::next_frame<UsFrame>(w, snap);
  ASSERT_EQ(base.transverse.size(), 128u * 128u);
  ASSERT_EQ(base.sagittal.size(), 128u * 128u);

  UsControls c = c0;
  c.gain_db = 12.0;
  w.set_controls(c);
  const UsFrame brighter = test::next_frame<UsFrame>(w, snap);
  ASSERT_EQ(brighter.transverse.size(), 128u * 128u);
  // +12 dB over a 60 dB range is +51 gray levels where nothing saturates: the mean rises by tens
  for (auto im : {&UsFrame::transverse, &UsFrame::sagittal}) {
    const double m0 = mean_where_lit(base.*im, base.*im), m1 = mean_where_lit(brighter.*im, base.*im);
    std::printf("mean gray in view: %.1f at 0 dB, %.1f at +12 dB\n", m0, m1);
    EXPECT_GT(m1, m0 + 30.0);
  }

  c.gain_db = 0.0;
  c.depth_m = 0.040;  // shallower: the gland fills more of the picture, the image differs
  w.set_controls(c);
  const UsFrame shallow = test::next_frame<UsFrame>(w, snap);
  EXPECT_NE(shallow.transverse, base.transverse);

  UsControls bad = c;
  bad.frequency_hz = 50e6;
  try {
    w.set_controls(bad);
    FAIL() << "50 MHz accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frequency"), std::string::npos) << e.what();
  }
  EXPECT_EQ(w.controls().frequency_hz, c.frequency_hz);  // refused: nothing changed
  EXPECT_EQ(w.controls().depth_m, 0.040);
}

// The window takes every image into the same UsFrame; the frames go back and forth between the
// worker and the window by swaps, so each must carry its own size (the window sizes the texture
// upload, the isodose lines and the template's marks by it). A frame of size 0 once came back
// every third image: the panel then skipped the upload and drew the overlays at the wrong scale.
TEST(UltrasoundWorker, EveryImageTakenIntoTheSameFrameCarriesItsSize) {
  Scene scene = load_scene(PROSTATESIM_SOURCE_DIR "/config/biopsy.yaml");
  LockstepRunner run(*scene.sim);
  const Snapshot snap = run.snapshot();
  UltrasoundWorker w(scene, 96);
  UsFrame f;  // reused, as UsPanel::frame
  for (int i = 0; i < 5; ++i) {
    w.submit(snap);
    bool got = false;
    for (int k = 0; k < 3000 && !(got = w.take(f)); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_TRUE(got) << "image " << i;
    EXPECT_EQ(f.side, 96) << "image " << i;
    EXPECT_EQ(f.transverse.size(), 96u * 96u) << "image " << i;
  }
}

}  // namespace
}  // namespace ps::gui
