#include "engine/dosimetry/live_dosimetry.h"

#include <algorithm>
#include <cmath>

#include "engine/dosimetry/organ_mask.h"

namespace ps::dosimetry {

namespace {
// seeds the tissue moved that one update re-adds (two passes each, ~3 ms of CPU per pass for a
// 1 mm grid over a 36 cc gland + 10 mm): the others follow in the next updates
constexpr int kMovedPerUpdate = 2;
}  // namespace

LiveDosimetry::LiveDosimetry(const SourceModel& s, const GridSpec& g, std::vector<std::array<int, 3>> pf,
                             std::vector<std::array<int, 3>> rf, double rx, double urethra_radius_mm)
    : acc_(s, g), prostate_faces_(std::move(pf)), rectum_faces_(std::move(rf)), rx_(rx), urethra_radius_mm_(urethra_radius_mm) {}

const LiveDosimetry::Result& LiveDosimetry::update(const std::vector<Seed>& seeds, const std::vector<Vec3>& pv,
                                                   const std::vector<Vec3>& rv, const std::vector<Vec3>& urethra) {
  result_.seed_passes = acc_.update(seeds, 0.25, kMovedPerUpdate);
  const GridSpec& g = acc_.spec();
  mask_.assign(g.size(), 0);
  fill_closed_surface(g, pv, prostate_faces_, kProstate, mask_);
  if (!rv.empty()) {
    fill_closed_surface(g, rv, rectum_faces_, kRectum, mask_);
    clear_where(mask_, kRectum, kProstate);
  }
  if (urethra.size() >= 2) fill_tube(g, urethra, urethra_radius_mm_, kUrethra, mask_);
  result_.indices = dosimetry_indices(g, acc_.dose_gy(), mask_, rx_, static_cast<int>(seeds.size()));
  result_.dvh = dvh_curve(acc_.dose_gy(), mask_, rx_);
  return result_;
}

std::shared_ptr<const DoseField> LiveDosimetry::field() const {
  auto f = std::make_shared<DoseField>();
  f->spec = acc_.spec();
  f->dose_gy = acc_.dose_gy();
  f->prescription_gy = rx_;
  return f;
}

double LiveDosimetry::dose_at(const Vec3& p) const {
  const GridSpec& g = acc_.spec();
  const Vec3 q = (p - g.origin_mm) / g.spacing_mm;
  if (q.x() < 0 || q.y() < 0 || q.z() < 0 || q.x() > g.nx - 1 || q.y() > g.ny - 1 || q.z() > g.nz - 1) return 0.0;
  const int i = std::min(static_cast<int>(q.x()), g.nx - 2), j = std::min(static_cast<int>(q.y()), g.ny - 2),
            k = std::min(static_cast<int>(q.z()), g.nz - 2);
  if (i < 0 || j < 0 || k < 0) return 0.0;
  const double u = q.x() - i, v = q.y() - j, w = q.z() - k;
  const auto& d = acc_.dose_gy();
  auto at = [&](int a, int b, int c) { return static_cast<double>(d[g.index(i + a, j + b, k + c)]); };
  const double c00 = at(0, 0, 0) * (1 - u) + at(1, 0, 0) * u, c10 = at(0, 1, 0) * (1 - u) + at(1, 1, 0) * u;
  const double c01 = at(0, 0, 1) * (1 - u) + at(1, 0, 1) * u, c11 = at(0, 1, 1) * (1 - u) + at(1, 1, 1) * u;
  return ((c00 * (1 - v) + c10 * v) * (1 - w) + (c01 * (1 - v) + c11 * v) * w);
}

}  // namespace ps::dosimetry
