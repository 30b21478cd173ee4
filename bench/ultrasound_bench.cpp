// Simulated TRUS image cost (engine/ultrasound/imager.h), one 512 x 512 plane per iteration, in
// the default anatomy (config/biopsy.yaml, ~3.7k particles) deformed by a smooth field, with a
// needle crossing the transverse plane and lying in the sagittal plane:
//  - BM_UltrasoundTransverse / BM_UltrasoundSagittal: one plane (issue 12 target: <= 10 ms on
//    one core);
//  - BM_UltrasoundBiplane: both planes, what the app draws every frame.
#include <benchmark/benchmark.h>

#include "tests/engine/ultrasound/us_scenes.h"

namespace ps::bench {

namespace {

struct UsBench {
  std::vector<float> x;
  us::UltrasoundScene scene;
};

UsBench& us_bench() {
  static UsBench b = [] {
    const auto& S = test::us_biopsy_scene();
    UsBench u;
    u.x = test::rest_positions(*S.model);
    for (size_t p = 0; p < S.model->rest_pos.size(); ++p) {
      const Vec3 X = S.model->rest_pos[p];
      u.x[3 * p] += static_cast<float>(1.5e-3 * std::sin(X.y() / 0.015));
      u.x[3 * p + 1] += static_cast<float>(1.5e-3 * std::sin(X.z() / 0.012));
    }
    u.scene.x = u.x.data();
    u.scene.particle_count = static_cast<int>(u.x.size() / 3);
    u.scene.probe = S.probe;
    us::Rod needle;
    needle.a = S.probe.tip_centre + 0.025 * S.probe.anterior + 0.02 * S.probe.axis;
    needle.b = needle.a - 0.1 * S.probe.axis;
    u.scene.rods.push_back(needle);
    return u;
  }();
  return b;
}

void BM_UltrasoundPlane(benchmark::State& state, us::PlaneKind kind) {
  const auto& S = test::us_biopsy_scene();
  UsBench& b = us_bench();
  us::PlaneImager im(S.anatomy, S.settings, kind);
  im.render(b.scene);  // warm
  for (auto _ : state) benchmark::DoNotOptimize(im.render(b.scene).pixels.data());
  state.counters["px"] = S.settings.width * S.settings.height;
}

void BM_UltrasoundTransverse(benchmark::State& state) { BM_UltrasoundPlane(state, us::PlaneKind::Transverse); }
void BM_UltrasoundSagittal(benchmark::State& state) { BM_UltrasoundPlane(state, us::PlaneKind::Sagittal); }

void BM_UltrasoundBiplane(benchmark::State& state) {
  const auto& S = test::us_biopsy_scene();
  UsBench& b = us_bench();
  us::BiplaneImager im(S.anatomy, S.settings);
  im.render(b.scene);
  for (auto _ : state) {
    im.render(b.scene);
    benchmark::DoNotOptimize(im.transverse().image().pixels.data());
  }
}

}  // namespace

BENCHMARK(BM_UltrasoundTransverse)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UltrasoundSagittal)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UltrasoundBiplane)->Unit(benchmark::kMillisecond);

}  // namespace ps::bench
