// A scene with its script, run in lockstep (no thread, no clock): `prostatesim bench`'s real-time
// figures (app/cmd_bench.cpp) and the bench modes that trace a scripted run tick by tick
// (bench/speed_trace.cpp, bench/tick_trace.cpp). The script is parsed first, so a bad script is
// reported before the scene is compiled.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>

#include "engine/realtime/lockstep.h"
#include "engine/realtime/script.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/sim/scene.h"

namespace ps {

struct ScriptedRun {
  ScriptedRun(const ScenarioSpec& spec, const std::string& script_file)
      : script(parse_script_file(script_file)), sc(build_scene(spec)), player(script_commands(script, sc)), run(*sc.sim) {
    run.add_source(&player);
  }
  int64_t ticks() const { return std::llround(script.duration / sc.model->dt); }  // the script's length

  Script script;
  Scene sc;
  CommandPlayer player;
  LockstepRunner run;
};

}  // namespace ps
