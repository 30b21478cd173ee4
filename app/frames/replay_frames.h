// The frames path of `prostatesim replay` (seam: app/core/run_session.h): the options --out DIR
// [--size WxH] [--fps N] [--views 3d,...] [--force] [--displacement], and the run that steps the
// lock-step runner to the end tick, feeds every tick's snapshot to a FrameRecorder (event log,
// force versus depth) and renders a frame every 1/fps simulated seconds (and the last tick).
// Bad options, an output folder that is not empty (without --force) or not writable, and no
// headless OpenGL are refused before anything is written.
#pragma once
#include <cstdint>
#include <string>

#include "app/frames/frame_recorder.h"
#include "app/core/run_session.h"

namespace ps::frames {

struct ReplayFramesResult {
  FrameSummary summary;
  int64_t ticks = 0;
  bool faulted = false;
  std::string fault;
  double wall_s = 0.0;            // [s]
};

// Runs `run` from its current tick to `end_tick`. `opt` checked and the folder prepared here.
ReplayFramesResult replay_frames(const Scene& scene, LockstepRunner& run, int64_t end_tick, FrameOptions opt);

// The frontend registered with app::register_replay_frames in main().
app::ReplayFrames replay_frames_frontend();

}  // namespace ps::frames
