#include "app/frames/snapshot_dose.h"

#include "engine/metrics/implant_dosimetry.h"
#include "engine/metrics/metrics_options.h"
#include "engine/sim/scene.h"
#include "engine/util/error.h"

namespace ps::frames {

namespace {

// particle indices of a component's surface in the order organ_surface_mm numbers them
std::vector<int> surface_ids(const Model& m, int c) {
  if (c < 0 || m.components[static_cast<size_t>(c)].surface < 0) return {};
  return m.surfaces[static_cast<size_t>(m.components[static_cast<size_t>(c)].surface)].vertices;
}

}  // namespace

bool SnapshotDose::scene_has_seeds(const Scene& scene) {
  for (const NeedleSpec& n : scene.spec.needles.needles)
    if (!n.seed_depths.empty()) return true;
  return false;
}

SnapshotDose::SnapshotDose(const Scene& scene, const std::string& isotope, double rx, double strength_u)
    : model_(scene.model.get()), strength_u_(strength_u) {
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
}

void SnapshotDose::seeds_of(const Snapshot& snap, std::vector<dosimetry::Seed>& out) const {
  out.clear();
  for (const DrawCapsule& c : snap.draw.capsules)
    if (c.role == DrawRole::Seed) out.push_back({500.0 * (c.a + c.b), (c.b - c.a).normalized(), strength_u_});
}

const dosimetry::LiveDosimetry::Result& SnapshotDose::update(const std::vector<float>& xf,
                                                             const std::vector<dosimetry::Seed>& seeds) {
  const size_t np = xf.size() / 3;
  if (np != static_cast<size_t>(model_->particle_count()))
    throw std::invalid_argument("dose: " + std::to_string(np) + " particle positions for a model of " +
                                std::to_string(model_->particle_count()));
  x_.resize(np);
  for (size_t i = 0; i < np; ++i) x_[i] = Vec3(xf[3 * i], xf[3 * i + 1], xf[3 * i + 2]);
  pv_.clear();
  rv_.clear();
  uv_.clear();
  for (int p : prostate_ids_) pv_.push_back(1e3 * x_[static_cast<size_t>(p)]);
  for (int p : rectum_ids_) rv_.push_back(1e3 * x_[static_cast<size_t>(p)]);
  for (const TrackedPoint& u : urethra_) uv_.push_back(1e3 * u.position(x_));
  return live_->update(seeds, pv_, rv_, uv_);
}

const dosimetry::LiveDosimetry::Result& SnapshotDose::update(const Snapshot& snap) {
  seeds_of(snap, seeds_);
  return update(snap.x, seeds_);
}

std::shared_ptr<const dosimetry::DoseField> SnapshotDose::field() const { return live_->field(); }

}  // namespace ps::frames
