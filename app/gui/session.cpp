#include "app/gui/session.h"

#include <algorithm>

#include "engine/tools/needle/needle.h"
#include "engine/util/error.h"
#include "engine/tools/probe/probe.h"

namespace ps::gui {

void Session::make_renderer() {
  renderer_ = std::make_unique<render::Renderer>(render::make_render_scene(scene_->spec, *scene_->model));
}

Session::Session(app::RunSession& run)
    : file_(run.scenario_path), scene_(&run.scene), loop_(&run.loop), mouse_(run.mouse), end_tick_(run.end_tick), run_records_(run.records) {
  make_renderer();
}

Session::Session(const std::string& scenario, double factor, const std::string& record_to) : file_(scenario) {
  own_scene_ = std::make_unique<Scene>(load_scene(scenario));
  scene_ = own_scene_.get();
  make_renderer();
  LoopOptions lo;
  lo.factor = factor;
  lo.log_timing = false;
  own_loop_ = std::make_unique<PhysicsLoop>(*scene_->sim, lo);
  loop_ = own_loop_.get();
  if (!record_to.empty()) {
    const Model& m = *scene_->model;
    recorder_ = std::make_unique<RecordingWriter>(record_to, RecordingHeader{scene_->spec.name, scene_->content_hash, m.dt, m.substeps});
    loop_->applier().set_observer(recorder_.get());
    loop_->set_hash_observer(recorder_.get(), recorder_->hash_every());
  }
  watchdog_ = std::make_unique<Watchdog>(*scene_->model);  // recovery as in cmd_run
  loop_->set_watchdog(watchdog_.get());
  loop_->keep_last_good(true);
  loop_->start();
}

Session::~Session() {
  if (!own_loop_) return;  // the run command stops its own loop
  own_loop_->stop();
  if (recorder_) recorder_->finish(own_loop_->tick(), scene_->sim->hash());
}

const std::string& Session::recording_path() const {
  static const std::string none;
  return recorder_ ? recorder_->path() : none;
}

const Snapshot& Session::latest() {
  fresh_ = loop_->update_snapshot();
  const Snapshot& s = loop_->snapshot();
  if (fresh_) {
    // a restart keeps counting, so the seqs only go up within this session's loop
    first_new_event_ = 0;
    while (first_new_event_ < s.events.size() && s.events[first_new_event_].seq <= taken_event_seq_) ++first_new_event_;
    if (!s.events.empty()) taken_event_seq_ = std::max(taken_event_seq_, s.events.back().seq);
  }
  return s;
}

std::span<const SnapshotEvent> Session::new_events() const {
  if (!fresh_) return {};
  const auto& e = loop_->snapshot().events;
  return {e.data() + first_new_event_, e.size() - first_new_event_};
}

void Session::pause(bool p) {
  if (p) loop_->pause();
  else loop_->resume();
}

SavedState Session::load_state(const std::string& path) {
  if (recording() || run_records_)
    throw InputError(path, 0, "", "this session is being recorded from its start: stop recording before loading a state");
  SavedState st = read_state_file(path);
  check_state_matches(st, scene_->spec.name, scene_->content_hash);
  loop_->load_state(st);
  return st;
}

void Session::push(Command c) {
  c.tick = loop_->next_tick();
  loop_->queue().push(c);  // a full queue drops the command: the physics never waits
}

void Session::move_probe(double insertion, double roll, double tilt, double yaw) {
  if (!has_probe()) return;
  Command c;
  c.kind = CommandKind::ProbeMove;
  c.tool = static_cast<int16_t>(scene_->tools.index<ProbeTool>());
  const ProbePose p0 = initial_probe_pose();
  c.probe.insertion = insertion;
  for (int k = 0; k < 3; ++k) c.probe.offset[k] = p0.offset[k];
  c.probe.roll = roll;
  c.probe.tilt = tilt;
  c.probe.yaw = yaw;
  c.probe.duration = 0.3;
  push(c);
}

int Session::needle_count() const {
  if (!scene_->tools.has<NeedleTool>()) return 0;
  return scene_->tools.as<NeedleTool>()->count();
}

std::string Session::needle_name(int i) const {
  if (i < 0 || i >= needle_count()) return "-";
  return scene_->tools.as<NeedleTool>()->spec(i).name;
}

namespace {
Command needle_command(CommandKind k, int tool, int i) {
  Command c;
  c.kind = k;
  c.tool = static_cast<int16_t>(tool);
  c.item = static_cast<int16_t>(i);
  return c;
}
}  // namespace

void Session::select(int i) {
  if (i >= 0 && i < needle_count()) push(needle_command(CommandKind::SelectNeedle, scene_->tools.index<NeedleTool>(), i));
}
void Session::advance(int i, double speed) {
  if (i < 0 || i >= needle_count()) return;
  Command c = needle_command(CommandKind::NeedleAdvance, scene_->tools.index<NeedleTool>(), i);
  c.needle.speed = speed;
  push(c);
}
void Session::fire(int i) {
  if (i >= 0 && i < needle_count()) push(needle_command(CommandKind::FireGun, scene_->tools.index<NeedleTool>(), i));
}
void Session::seed(int i) {
  if (i >= 0 && i < needle_count()) push(needle_command(CommandKind::DepositSeed, scene_->tools.index<NeedleTool>(), i));
}
void Session::aim_hole(int i, int col, int row) {
  if (i < 0 || i >= needle_count()) return;
  Command c = needle_command(CommandKind::SelectHole, scene_->tools.index<NeedleTool>(), i);
  c.needle.col = col;
  c.needle.row = row;
  push(c);
}

}  // namespace ps::gui
