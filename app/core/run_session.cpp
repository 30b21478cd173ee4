// The seams of app/core/run_session.h: the registered frontends, and the recovery helpers that
// run, replay and the trainee window share.
#include "app/core/run_session.h"

#include <cstdio>
#include <exception>

#include "engine/util/error.h"

namespace ps::app {

namespace {
WindowFrontend g_window = nullptr;
ReplayFrames g_frames;
}  // namespace

void register_window_frontend(WindowFrontend f) { g_window = f; }
WindowFrontend window_frontend() { return g_window; }

void register_replay_frames(ReplayFrames f) { g_frames = f; }
const ReplayFrames& replay_frames() { return g_frames; }

FaultInjection parse_fault_injection(const std::string& spec) {
  FaultInjection f;
  if (spec.empty()) return f;
  const auto at = spec.find('@');
  const std::string kind = spec.substr(0, at);
  if (at == std::string::npos || (kind != "nan" && kind != "throw"))
    throw InputError("", 0, "--inject-fault", "expected nan@TICK or throw@TICK, got '" + spec + "'");
  try {
    f.tick = std::stoll(spec.substr(at + 1));
  } catch (const std::exception&) {
    throw InputError("", 0, "--inject-fault", "expected nan@TICK or throw@TICK, got '" + spec + "'");
  }
  f.internal = kind == "throw";
  return f;
}

void save_fault_state(const std::string& path, SavedState st, const Scene& scene) {
  st.scenario = scene.spec.name;
  st.scenario_hash = scene.content_hash;
  write_state_file(path, st);
  std::fprintf(stderr, "last good state (tick %lld, t=%.4f s, state hash %s) saved to %s\n", static_cast<long long>(st.tick), st.time,
               hex16(st.state_hash).c_str(), path.c_str());
}

}  // namespace ps::app
