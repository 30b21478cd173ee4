// `prostatesim_bench --realtime [WALL_S]`: the real-time physics thread on each default scene with
// its script (config/scripts/<scene>.yaml; bladder_filling runs its own schedule), paced at real
// time (factor 1) for WALL_S seconds of wall time each (default 20): achieved tick rate,
// real-time factor, compute per tick p50 / p99 / max, jitter of tick starts (p99 - p50),
// overruns, re-anchors (slow motion), snapshot publish time, and the heaviest stages. A scene
// heavier than real time shows up as a real-time factor below 1 and re-anchors, never as a
// growing backlog. Figures are of the last one-second window and of the whole run.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>

#include "bench/bench_modes.h"
#include "engine/realtime/physics_loop.h"
#include "engine/realtime/script.h"
#include "engine/sim/scene.h"

namespace ps::bench {

int realtime_loop(double wall_s) {
  const std::string dir = std::string(PROSTATESIM_SOURCE_DIR) + "/config/";
  int bad = 0;
  for (const char* name : {"biopsy", "brachytherapy", "bladder_filling"}) {
    Scene sc = load_scene(dir + name + ".yaml");
    std::unique_ptr<CommandPlayer> player;
    const std::string script = dir + "scripts/" + name + ".yaml";
    if (std::filesystem::exists(script)) player = std::make_unique<CommandPlayer>(script_commands(parse_script_file(script), sc));
    LoopOptions opt;
    opt.log_timing = false;
    PhysicsLoop loop(*sc.sim, opt);
    if (player) loop.add_source(player.get());
    const auto t0 = std::chrono::steady_clock::now();
    loop.start();
    std::this_thread::sleep_for(std::chrono::duration<double>(wall_s));
    loop.stop();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const LoopTiming t = loop.timing();
    const double sim_t = sc.sim->state().time;
    std::printf("%-16s %6d particles, tick %.0f ms x %2d substeps%s\n", name, sc.model->particle_count(), sc.model->dt * 1e3,
                sc.model->substeps, player ? ", scripted" : "");
    std::printf("  whole run: %lld ticks in %.1f s wall = %.1f ticks/s, real-time factor %.3f\n", static_cast<long long>(loop.tick()),
                wall, loop.tick() / wall, sim_t / wall);
    std::printf("  last window: %.1f ticks/s, real-time factor %.3f%s; compute per tick p50 %.2f ms, p99 %.2f ms, max %.2f ms; "
                "jitter (p99-p50 of tick starts) %.2f ms\n",
                t.achieved_hz, t.realtime_factor, t.slow_motion ? " (slow motion)" : "", t.tick_p50_ms, t.tick_p99_ms, t.tick_max_ms,
                t.jitter_ms);
    std::printf("  whole run: compute per tick p50 %.2f ms, p99 %.2f ms, max %.2f ms\n", t.run_tick_p50_ms, t.run_tick_p99_ms,
                t.run_tick_max_ms);
    std::printf("  overruns %lld of %lld ticks, re-anchors %lld, publish %.3f ms/tick, commands %lld applied %lld refused\n",
                static_cast<long long>(t.overruns), static_cast<long long>(t.ticks), static_cast<long long>(t.reanchors), t.publish_ms,
                static_cast<long long>(t.commands_applied), static_cast<long long>(t.commands_refused));
    std::printf("  stages [ms/tick]:");
    for (int i = 0; i < kStageCount; ++i)
      if (t.stage_ms[i] > 0.01 * t.tick_p50_ms) std::printf(" %s %.2f", stage_name(static_cast<Stage>(i)), t.stage_ms[i]);
    std::printf("\n");
    if (loop.faulted()) {
      std::printf("  FAULT: %s\n", sc.sim->state().fault.describe(*sc.model).c_str());
      ++bad;
    }
  }
  return bad ? 1 : 0;
}

}  // namespace ps::bench
