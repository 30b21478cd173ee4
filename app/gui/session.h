// One running scene of the trainee window: either the run command's own (borrowed: its scene,
// physics thread and mouse/keyboard device) or one the window opened itself (owned: a scenario
// opened from the window, or a fresh start being recorded). The window talks to the physics only
// through this: it reads the newest snapshot and pushes stamped commands.
#pragma once
#include <memory>
#include <span>
#include <string>

#include "app/core/run_session.h"
#include "engine/sim/watchdog.h"
#include "engine/tools/probe/probe.h"
#include "render/renderer.h"

namespace ps::gui {

class Session {
 public:
  explicit Session(app::RunSession& run);  // borrowed
  // Owned: loads, compiles and starts the scenario (recording every applied command to
  // `record_to` when given); throws InputError / CompileError (file:line:field), leaving
  // nothing running.
  Session(const std::string& scenario, double factor, const std::string& record_to = "");
  ~Session();

  const std::string& name() const { return scene_->spec.name; }
  const Scene& scene() const { return *scene_; }
  const std::string& file() const { return file_; }
  render::Renderer& renderer() { return *renderer_; }
  haptics::MouseKeyboardDevice* mouse() const { return mouse_; }
  int64_t end_tick() const { return end_tick_; }
  PhysicsLoop& loop() { return *loop_; }

  // Newest snapshot; new_events(): its events not taken before (a snapshot carries every event
  // the reader may have missed, so those already taken are skipped by SnapshotEvent::seq).
  const Snapshot& latest();
  std::span<const SnapshotEvent> new_events() const;
  LoopTiming timing() const { return loop_->timing(); }

  void pause(bool p);
  void restart() { loop_->reset(); }
  // Goes on from a saved state file of this scenario (PhysicsLoop::load_state). Returns the state
  // loaded; throws InputError naming the file, line and field (another scenario, a damaged file,
  // a session being recorded: a recording covers a session from its start), nothing changed.
  SavedState load_state(const std::string& path);

  bool has_probe() const { return scene_->tools.has<ProbeTool>(); }
  ProbePose initial_probe_pose() const { return scene_->spec.probe ? scene_->spec.probe->pose : ProbePose{}; }
  void move_probe(double insertion, double roll, double tilt, double yaw);

  int needle_count() const;
  std::string needle_name(int i) const;
  void select(int i);
  void advance(int i, double speed);  // [m/s], negative retracts, 0 stops
  void fire(int i);
  void seed(int i);
  // needle i to template hole (col, row) of the probe's stepper: tip at the template, held
  // (CommandKind::SelectHole; the tool refuses a hole outside the grid or a guided needle)
  void aim_hole(int i, int col, int row);

  bool recording() const { return recorder_ != nullptr; }
  const std::string& recording_path() const;

 private:
  void make_renderer();
  void push(Command c);

  std::string file_;
  std::unique_ptr<Scene> own_scene_;
  std::unique_ptr<RecordingWriter> recorder_;
  std::unique_ptr<Watchdog> watchdog_;
  std::unique_ptr<PhysicsLoop> own_loop_;
  Scene* scene_ = nullptr;
  PhysicsLoop* loop_ = nullptr;
  haptics::MouseKeyboardDevice* mouse_ = nullptr;
  int64_t end_tick_ = -1;
  std::unique_ptr<render::Renderer> renderer_;
  bool fresh_ = false;
  size_t first_new_event_ = 0;     // in the latest snapshot's events
  uint64_t taken_event_seq_ = 0;   // the newest event seq taken
  bool run_records_ = false;       // the borrowed run writes a recording (--record)
};

}  // namespace ps::gui
