// Headless frame time of the default biopsy scene at 1280x720 on whatever GL the machine has
// (llvmpipe here): snapshot upload + draw + read-back, the render thread's share of a replay
// frame. PNG encoding, and with --aa fxaa the antialiasing pass, run on the encoder thread.
// Target from issue 11: <= 15 ms per frame on llvmpipe.
//   NoMsaa_Readback  the render thread with --aa fxaa (the default on a software rasteriser)
//   Fxaa_Serial      the same plus the FXAA pass on the same thread (its cost if nothing overlapped)
//   Msaa4_*          --aa msaa (the default on a hardware GL)
//   ./build/bench/render/render_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <ctime>
#include <memory>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/script.h"
#include "engine/sim/scene.h"
#include "render/gl_api.h"
#include "render/headless_context.h"
#include "render/post_antialias.h"
#include "render/offscreen_target.h"
#include "render/renderer.h"

namespace {

struct Fixture {
  ps::render::HeadlessContext ctx;
  ps::Scene scene = ps::load_scene(PROSTATESIM_SOURCE_DIR "/config/biopsy.yaml");
  std::unique_ptr<ps::CommandPlayer> script;
  std::unique_ptr<ps::LockstepRunner> run;
  std::unique_ptr<ps::render::Renderer> renderer;
  ps::Snapshot snap;
  Fixture() {
    run = std::make_unique<ps::LockstepRunner>(*scene.sim);
    script = std::make_unique<ps::CommandPlayer>(
        ps::script_commands(ps::parse_script_file(PROSTATESIM_SOURCE_DIR "/config/scripts/biopsy.yaml"), scene));
    run->add_source(script.get());
    run->advance_to(static_cast<int64_t>(0.6 / scene.model->dt));  // needle in the gland
    snap = run->snapshot();
    renderer = std::make_unique<ps::render::Renderer>(ps::render::make_render_scene(*scene.model));
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void frame(benchmark::State& st, bool readback, int samples, bool fxaa = false) {
  Fixture& f = fixture();
  const int w = 1280, h = 720;
  ps::render::OffscreenTarget target(w, h, samples);
  ps::render::OrbitCamera orbit;
  orbit.target = f.renderer->scene().focus;
  orbit.distance = f.renderer->scene().extent * 3.2;
  const ps::render::Camera cam = ps::render::preset_camera(ps::render::View::Orbit, f.renderer->scene(), &f.snap, orbit);
  ps::render::RenderOptions opt;
  std::vector<uint8_t> rgb, out(3 * static_cast<size_t>(w) * h);
  std::vector<uint8_t> luma;
  // process CPU time (all threads: llvmpipe rasterises on its own threads): on a shared machine
  // the wall time includes waiting for a core, the CPU time does not
  auto cpu_now = [] {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;  // [ms]
  };
  const double cpu0 = cpu_now();
  for (auto _ : st) {
    f.renderer->update(f.snap);
    target.bind();
    f.renderer->render(cam, w, h, opt);
    if (readback) target.read_rgb(rgb);
    else ps::gl::api.Finish();
    if (fxaa) ps::render::fxaa_rgb(rgb.data(), w, h, out.data(), luma);
  }
  st.counters["cpu_ms_all_threads"] = (cpu_now() - cpu0) / static_cast<double>(st.iterations());
}

void BM_BiopsyFrame720p_Msaa4_Readback(benchmark::State& st) { frame(st, true, 4); }
void BM_BiopsyFrame720p_Msaa4_NoReadback(benchmark::State& st) { frame(st, false, 4); }
void BM_BiopsyFrame720p_NoMsaa_Readback(benchmark::State& st) { frame(st, true, 0); }
BENCHMARK(BM_BiopsyFrame720p_Msaa4_Readback)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_BiopsyFrame720p_Msaa4_NoReadback)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_BiopsyFrame720p_NoMsaa_Readback)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
void BM_BiopsyFrame720p_Fxaa_Serial(benchmark::State& st) { frame(st, true, 0, true); }
BENCHMARK(BM_BiopsyFrame720p_Fxaa_Serial)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
