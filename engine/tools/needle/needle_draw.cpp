// How needles look (Tool::draw, engine/draw/draw_sink.h): steel shaft from tip to hub at the
// needle's true radius, a red tip, dark depth marks every 10 mm from the tip (as on clinical
// needles), the hub / gun body, deposited seeds (I-125 size: 4.5 mm x 0.8 mm) where the tissue
// carries them, and the tissue force on the needle as an arrow at the tip (5 mm per N).
#include <algorithm>
#include <cmath>

#include "engine/tools/needle/needle.h"
#include "engine/tools/needle/needle_internal.h"

namespace ps {

namespace {
constexpr double kMarkSpacing = 10e-3;   // depth marks [m]
constexpr double kMarkLength = 0.8e-3;   // [m]
constexpr double kArrowPerNewton = 5e-3; // force arrow scale [m/N]
constexpr double kSeedLength = 4.5e-3, kSeedRadius = 0.4e-3;  // [m]
constexpr double kHubLength = 15e-3, kHubRadius = 3e-3;       // [m]
}  // namespace

void NeedleTool::draw(DrawSink& out, const Model&, const State&) const {
  const Rgba steel{0.78f, 0.80f, 0.84f, 1.0f}, mark{0.12f, 0.12f, 0.14f, 1.0f}, tip{0.90f, 0.10f, 0.10f, 1.0f};
  const Rgba hub{0.25f, 0.45f, 0.85f, 1.0f}, seed{0.95f, 0.80f, 0.30f, 1.0f}, force{1.0f, 0.55f, 0.0f, 1.0f};
  for (const auto& p : needles_) {
    const Needle& nd = *p;
    const Vec3 back = nd.T - nd.spec.length * nd.d;
    out.capsule(nd.T, back, nd.radius, steel, DrawRole::Needle);
    for (double s = kMarkSpacing; s < nd.spec.length - kHubLength; s += kMarkSpacing) {
      const Vec3 c = nd.T - s * nd.d;
      const double r = (std::fmod(s + 1e-6, 5 * kMarkSpacing) < 1e-5) ? 1.6 * nd.radius : 1.25 * nd.radius;
      out.capsule(c - 0.5 * kMarkLength * nd.d, c + 0.5 * kMarkLength * nd.d, r, mark, DrawRole::DepthMark);
    }
    out.sphere(nd.T, std::max(1.0e-3, 1.6 * nd.radius), tip, DrawRole::NeedleTip);
    out.capsule(back, back - kHubLength * nd.d, kHubRadius, hub, DrawRole::Needle);
    for (const SeedState& sd : nd.seeds)
      if (sd.deposited)
        out.capsule(sd.current - 0.5 * (kSeedLength - 2 * kSeedRadius) * nd.spec.direction,
                    sd.current + 0.5 * (kSeedLength - 2 * kSeedRadius) * nd.spec.direction, kSeedRadius, seed,
                    DrawRole::Seed);
    const Vec3 f = nd.ro.tissue_force;
    if (f.norm() > 0.05) out.arrow(nd.T, kArrowPerNewton * f, force, DrawRole::Force);
  }
}

}  // namespace ps
