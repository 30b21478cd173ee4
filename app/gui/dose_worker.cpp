#include "app/gui/dose_worker.h"

#include <chrono>

#include "engine/metrics/implant_dosimetry.h"
#include "engine/metrics/metrics_options.h"
#include "engine/model/model.h"
#include "engine/sim/scene.h"
#include "engine/util/error.h"

namespace ps::gui {

namespace {

// particle indices of a component's surface in the order organ_surface_mm numbers them
std::vector<int> surface_ids(const Model& m, int c) {
  if (c < 0 || m.components[static_cast<size_t>(c)].surface < 0) return {};
  return m.surfaces[static_cast<size_t>(m.components[static_cast<size_t>(c)].surface)].vertices;
}

}  // namespace

DoseWorker::DoseWorker(const Scene& scene, const std::string& isotope, double rx, double strength_u)
    : model_(scene.model.get()), rx_(rx), strength_u_(strength_u) {
  const Model& m = *model_;
  const MetricsOptions mo = metrics_options_for(scene.spec, m);
  const int gland = m.find_organ(mo.gland, Role::Prostate), rectum = m.find_role(Role::Rectum);
  const dosimetry::SourceModel* src = dosimetry::find_source_model(isotope);
  if (!src) throw InputError("", 0, "isotope", "unknown seed model '" + isotope + "'");
  std::vector<Vec3> pv, rv;
  std::vector<std::array<int, 3>> pf, rf;
  organ_surface_mm(m, gland, m.rest_pos, pv, pf);
  if (pv.empty()) throw InputError(scene.spec.file, 0, "components", "no gland surface to compute the dose on");
  organ_surface_mm(m, rectum, m.rest_pos, rv, rf);
  prostate_ids_ = surface_ids(m, gland);
  rectum_ids_ = surface_ids(m, rectum);
  for (const Vec3& u : mo.urethra) urethra_.push_back(track_point(m, u));
  live_ = std::make_unique<dosimetry::LiveDosimetry>(*src, dosimetry::gland_grid(pv), pf, rf, rx, kUrethraRadius * 1e3);
  thread_ = std::thread([this] { run(); });
}

DoseWorker::~DoseWorker() {
  {
    std::lock_guard<std::mutex> lk(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DoseWorker::submit(const Snapshot& snap) {
  size_t n = 0;
  for (const DrawCapsule& c : snap.draw.capsules) n += c.role == DrawRole::Seed;
  // a new update when a seed dropped, else every 25 ticks (the tissue carries the seeds)
  if (n == last_seeds_ && snap.tick - last_tick_ < 25) return;
  last_seeds_ = n;
  last_tick_ = snap.tick;
  std::lock_guard<std::mutex> lk(mu_);
  pending_.x = snap.x;
  pending_.time = snap.time;
  pending_.seeds.clear();
  for (const DrawCapsule& c : snap.draw.capsules)
    if (c.role == DrawRole::Seed)
      pending_.seeds.push_back({500.0 * (c.a + c.b), (c.b - c.a).normalized(), strength_u_});
  has_pending_ = true;
  cv_.notify_one();
}

bool DoseWorker::take(DoseFrame& out) {
  std::lock_guard<std::mutex> lk(mu_);
  if (!fresh_) return false;
  out = done_;
  fresh_ = false;
  return true;
}

void DoseWorker::run() {
  std::vector<Vec3> pv, rv, uv, x;
  for (;;) {
    {
      std::unique_lock<std::mutex> lk(mu_);
      cv_.wait(lk, [&] { return stop_ || has_pending_; });
      if (stop_) return;
      std::swap(working_, pending_);
      has_pending_ = false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const size_t np = working_.x.size() / 3;
    if (np != static_cast<size_t>(model_->particle_count())) continue;
    x.resize(np);
    for (size_t i = 0; i < np; ++i) x[i] = Vec3(working_.x[3 * i], working_.x[3 * i + 1], working_.x[3 * i + 2]);
    pv.clear();
    rv.clear();
    uv.clear();
    for (int p : prostate_ids_) pv.push_back(1e3 * x[static_cast<size_t>(p)]);
    for (int p : rectum_ids_) rv.push_back(1e3 * x[static_cast<size_t>(p)]);
    for (const TrackedPoint& u : urethra_) uv.push_back(1e3 * u.position(x));
    const auto& r = live_->update(working_.seeds, pv, rv, uv);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::lock_guard<std::mutex> lk(mu_);
    done_.ready = true;
    done_.seeds = static_cast<int>(working_.seeds.size());
    done_.time = working_.time;
    done_.ms = ms;
    done_.seed_passes = r.seed_passes;
    done_.indices = r.indices;
    done_.dvh = r.dvh;
    fresh_ = true;
  }
}

}  // namespace ps::gui
