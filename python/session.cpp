#include "python/session.h"

#include <stdexcept>

#include "engine/metrics/metrics_json.h"
#include "engine/metrics/metrics_options.h"
#include "engine/metrics/score.h"
#include "engine/realtime/script_entry.h"
#include "engine/realtime/state_file.h"
#include "engine/tools/needle/needle.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/util/error.h"

namespace ps::python {

// Feeds the needle session metrics after every tick (outside the step), as `run --report` does.
class Session::MetricsFeed final : public CommandSource {
 public:
  explicit MetricsFeed(const Scene& scene)
      : scene_(scene), needles_(*scene.tools.as<NeedleTool>()) {
    rewind();
  }
  void poll(int64_t, const Simulation&, CommandApplier&) override {}
  void after_tick(int64_t, const Simulation& sim) override { metrics_->observe(needles_, sim.state()); }
  void rewind() override { metrics_ = std::make_unique<SessionMetrics>(*scene_.model, needles_, metrics_options_for(scene_.spec, *scene_.model)); }
  std::string json(bool faulted) const {
    const SessionReport r = metrics_->finish(needles_, scene_.sim->state(), faulted);
    return ps::metrics_json(r, score_session(r), {});
  }

 private:
  const Scene& scene_;
  const NeedleTool& needles_;
  std::unique_ptr<SessionMetrics> metrics_;
};

Session::Session(const std::string& scenario_path) : scene_(load_scene(scenario_path)) {
  run_ = std::make_unique<LockstepRunner>(*scene_.sim);
  run_->runner().keep_last_good(true);
  if (scene_.tools.has<NeedleTool>()) {
    metrics_ = std::make_unique<MetricsFeed>(scene_);
    run_->add_source(metrics_.get());
  }
}

Session::~Session() = default;

bool Session::step(int64_t ticks) {
  if (ticks < 0) throw std::invalid_argument("step: ticks must be >= 0");
  return run_->advance_to(run_->tick() + ticks);
}

void Session::command(const std::string& entry_text) {
  const ScriptEntry e = parse_command_text(entry_text);
  TimelineMemory memory = timeline_;  // kept only when the command is taken
  const Command c = entry_command(e, scene_, run_->tick(), memory, "");
  const int64_t refused = run_->applier().refused();
  // applied now, between ticks: the state is the one a script stamped with this tick gives
  // (TickRunner::step applies its sources' commands at the same point, before the tick runs)
  if (!run_->applier().apply(c, run_->tick())) {
    const RefusalRing& rr = run_->applier().refusals();
    throw std::invalid_argument(rr.total() > refused ? rr.at(rr.size() - 1).describe() : "command refused");
  }
  timeline_ = memory;
}

ProbePose Session::probe_pose() const { return commanded_probe_pose(timeline_, scene_.spec); }

Snapshot Session::snapshot() {
  run_->runner().fill_snapshot(snap_, true);  // after the events an ultrasound() call took
  Snapshot out = snap_;
  snap_.events.clear();
  return out;
}

const us::UsImage& Session::ultrasound(const std::string& view) {
  const bool transverse = view == "transverse" || view == "us_transverse";
  if (!transverse && view != "sagittal" && view != "us_sagittal")
    throw InputError("", 0, "view", "unknown view '" + view + "' (transverse, sagittal)");
  if (!scene_.spec.probe) throw InputError(scene_.spec.file, 0, "probe", "the scenario has no probe: section to image from");
  if (!imager_) {
    anatomy_ = std::make_unique<us::UltrasoundAnatomy>(us::anatomy_for_scenario(scene_.spec, *scene_.model));
    imager_ = std::make_unique<us::BiplaneImager>(*anatomy_, us::settings_for_probe(*scene_.spec.probe));
  }
  // from a snapshot, as the window's and the OpenIGTLink server's images are
  run_->runner().fill_snapshot(snap_, true);  // its events wait for snapshot()
  us::ProbeView probe;
  us::probe_view_from_snapshot(snap_, probe);
  us::UltrasoundScene sc;
  us::scene_from_snapshot(snap_, probe, sc);
  us::PlaneImager& im = transverse ? imager_->transverse() : imager_->sagittal();
  return im.render(sc);
}

std::string Session::metrics_json() const {
  if (!metrics_) throw InputError(scene_.spec.file, 0, "needles", "the scenario has no needles: section (nothing to score)");
  return metrics_->json(run_->faulted());
}

void Session::save_state(const std::string& path) {
  SavedState st;
  run_->runner().current_state(st);
  st.scenario = scene_.spec.name;
  st.scenario_hash = scene_.content_hash;
  write_state_file(path, st);
}

void Session::load_state(const std::string& path) {
  const SavedState st = read_state_file(path);
  check_state_matches(st, scene_.spec.name, scene_.content_hash);
  run_->runner().load_state(st);
}

}  // namespace ps::python
