#include "app/session_capture.h"

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "app/session_report.h"
#include "engine/io/png_write.h"
#include "engine/metrics/metrics_json.h"
#include "engine/metrics/metrics_options.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps::app {

namespace {
const NeedleTool& needle_tool_of(const Scene& s) { return static_cast<const NeedleTool&>(*s.sim->tools().at(s.needle_tool)); }
}  // namespace

std::unique_ptr<SessionCapture> SessionCapture::make(const Scene& scene) {
  if (scene.needle_tool < 0) return nullptr;
  return std::unique_ptr<SessionCapture>(new SessionCapture(scene));
}

SessionCapture::SessionCapture(const Scene& scene) : scene_(scene), needles_(needle_tool_of(scene)) { rewind(); }

void SessionCapture::rewind() {
  metrics_ = std::make_unique<SessionMetrics>(*scene_.model, needles_, metrics_options_for(scene_.spec));
  rec_ = std::make_unique<ForceDepthRecorder>(needles_.count());
}

void SessionCapture::after_tick(int64_t, const Simulation& sim) {
  rec_->sample(needles_, sim.state().time);
  metrics_->observe(needles_, sim.state());
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
  const RgbImage page = render_session_report(m, scene_.sim->state(), needles_, *rec_, r, score);
  write_png_atomic(d + "report.png", page.width, page.height, 3, page.pixels.data());
  return score;
}

void prepare_report_dir(const std::string& dir, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (dir.empty()) throw InputError("", 0, option, "empty output folder");
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw InputError(dir, 0, option, "exists and is not a folder");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, 0, option, "cannot create the folder: " + ec.message());
  if (::access(dir.c_str(), W_OK) != 0) throw InputError(dir, 0, option, "the folder is not writable");
}

}  // namespace ps::app
