#include "app/session/session_capture.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "app/session/session_report.h"
#include "app/session/session_views.h"
#include "engine/tools/probe/probe.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/io/png_write.h"
#include "engine/metrics/metrics_json.h"
#include "engine/metrics/metrics_options.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"
#include "engine/tools/needle/needle.h"

namespace ps::app {

namespace {
const NeedleTool& needle_tool_of(const Scene& s) { return *s.tools.as<NeedleTool>(); }
}  // namespace

std::unique_ptr<SessionCapture> SessionCapture::make(const Scene& scene) {
  if (!scene.tools.has<NeedleTool>()) return nullptr;
  return std::unique_ptr<SessionCapture>(new SessionCapture(scene));
}

SessionCapture::SessionCapture(const Scene& scene) : scene_(scene), needles_(needle_tool_of(scene)) {
  gland_ = scene.model->find_role(Role::Prostate);
  if (scene.tools.has<ProbeTool>())
    for (Shot& sh : shots_) snapshot_of(*scene.sim, sh.snap);  // sizes the buffers once
  rewind();
}

void SessionCapture::rewind() {
  shots_used_ = 0;
  events_seen_ = needles_.events().total();
  metrics_ = std::make_unique<SessionMetrics>(*scene_.model, needles_, metrics_options_for(scene_.spec, *scene_.model));
  rec_ = std::make_unique<ForceDepthRecorder>(needles_.count());
}

void SessionCapture::after_tick(int64_t, const Simulation& sim) {
  rec_->sample(needles_, sim.state().time);
  metrics_->observe(needles_, sim.state());
  if (scene_.tools.has<ProbeTool>())
    metrics_->observe_probe(scene_.tools.as<ProbeTool>()->reaction_force().norm(),
                            scene_.model->dt);
  // one picture per tick at most: the first puncture or core of this tick; a puncture of the
  // gland or a core replaces an earlier puncture of another organ (the route) once the slots are full
  const NeedleEvent* ev = nullptr;
  bool key = false;
  events_seen_ = needles_.events().for_each_since(events_seen_, [&](const NeedleEvent& e) {
    const bool core = e.kind == NeedleEventKind::Core;
    if (e.kind != NeedleEventKind::Puncture && !core) return;
    const bool k = core || gland_ < 0 || e.component == gland_;
    if (!ev || (k && !key)) { ev = &e; key = k; }
  });
  if (!ev || !scene_.tools.has<ProbeTool>()) return;
  int slot = shots_used_ < kPunctureShots ? shots_used_ : -1;
  if (slot < 0 && key)
    for (int k = 0; k < kPunctureShots && slot < 0; ++k)
      if (!shots_[static_cast<size_t>(k)].key) slot = k;
  if (slot < 0) return;
  if (slot == shots_used_) ++shots_used_;
  Shot& sh = shots_[static_cast<size_t>(slot)];
  snapshot_of(sim, sh.snap);
  const auto& probe = *scene_.tools.as<ProbeTool>();
  sh.probe = us::probe_view(probe.frame(), probe.spec().radius);
  sh.time = ev->time;
  sh.depth = ev->depth;
  sh.force = ev->force;
  sh.needle = ev->needle;
  sh.component = ev->component;
  sh.core = ev->kind == NeedleEventKind::Core;
  sh.key = key;
}

SessionReport SessionCapture::report(bool faulted) const { return metrics_->finish(needles_, scene_.sim->state(), faulted); }

Score SessionCapture::write(const std::string& dir, bool faulted, const std::string& trainee, const std::string& session) const {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const std::string d = dir + "/";
  const Model& m = *scene_.model;
  for (int i = 0; i < needles_.count(); ++i) write_force_depth_csv(d + "force_depth_" + needles_.spec(i).name + ".csv", rec_->samples(i));
  write_file_atomic(d + "needle_events.csv", needle_events_csv(needles_, m));
  write_file_atomic(d + "seeds.csv", seeds_csv(needles_));
  write_file_atomic(d + "cores.csv", cores_csv(needles_));
  const SessionReport r = report(faulted);
  const Score score = score_session(r);
  const std::string name = !session.empty() ? session : fs::path(dir).lexically_normal().filename().string();
  write_file_atomic(d + "metrics.json", metrics_json(r, score, {trainee, name}));
  ReportViews views;
  Snapshot end;
  snapshot_of(*scene_.sim, end);
  views.view3d = render_3d_view(scene_, end, r, 800, 600, views.note3d);
  if (!scene_.tools.has<ProbeTool>() && scene_.spec.probe) views.note_us = "the probe is not simulated in this run (insert: needles only)";
  else if (!scene_.tools.has<ProbeTool>()) views.note_us = "no probe in this scenario: no ultrasound image";
  else if (shots_used_ == 0) views.note_us = "no puncture and no core in this session";
  // in time order (a replaced slot may hold a later event than the next one)
  std::array<int, kPunctureShots> order{};
  for (int k = 0; k < shots_used_; ++k) order[static_cast<size_t>(k)] = k;
  // insertion sort of at most kPunctureShots entries (std::sort here trips a false -Warray-bounds
  // in GCC 12's unrolled insertion step)
  for (int k = 1; k < shots_used_; ++k)
    for (int j = k; j > 0 && shots_[static_cast<size_t>(order[j])].time < shots_[static_cast<size_t>(order[j - 1])].time; --j)
      std::swap(order[static_cast<size_t>(j)], order[static_cast<size_t>(j - 1)]);
  for (int k = 0; k < shots_used_; ++k) {
    const Shot& sh = shots_[static_cast<size_t>(order[static_cast<size_t>(k)])];
    PunctureShot p;
    p.time = sh.time;
    p.depth = sh.depth;
    p.force = sh.force;
    p.needle = sh.needle >= 0 ? needles_.spec(sh.needle).name : "";
    p.organ = sh.core ? "core" : sh.component >= 0 ? m.components[static_cast<size_t>(sh.component)].name : "";
    p.us = render_us(scene_, sh.snap, sh.probe, sh.needle >= 0 ? needles_.spec(sh.needle).direction : Vec3::UnitZ(), 280);
    views.punctures.push_back(std::move(p));
  }
  const RgbImage page = render_session_report(m, scene_.sim->state(), needles_, *rec_, r, score, &views);
  write_png_atomic(d + "report.png", page.width, page.height, 3, page.pixels.data());
  return score;
}

}  // namespace ps::app
