#include "app/session/session_views.h"

#include <cmath>

#include "engine/ultrasound/from_simulation.h"
#include "engine/ultrasound/imager.h"
#include "engine/ultrasound/settings.h"
#include "render/headless_context.h"
#include "render/render_error.h"
#include "render/offscreen_target.h"
#include "render/renderer.h"

namespace ps::app {

void snapshot_of(const Simulation& sim, Snapshot& out) {
  const State& s = sim.state();
  out.x.resize(3 * s.x.size());
  for (size_t i = 0; i < s.x.size(); ++i)
    for (int k = 0; k < 3; ++k) out.x[3 * i + k] = static_cast<float>(s.x[i][k]);
  out.draw.clear();
  for (const auto& t : sim.tools()) t->draw(out.draw, sim.model(), s);
  out.time = s.time;
}

RgbImage render_3d_view(const Scene& scene, const Snapshot& snap0, const SessionReport& r, int w, int h, std::string& note) {
  RgbImage img;
  try {
    render::HeadlessContext ctx;
    render::Renderer rr(render::make_render_scene(scene.spec, *scene.model));
    Snapshot snap = snap0;
    // the report's markers: target carried by the tissue (red), where the needle put its sample (blue)
    for (const NeedleMetrics& n : r.needles) {
      snap.draw.sphere(n.scored ? n.target_now : n.target_rest, 2.5e-3, Rgba{0.9f, 0.1f, 0.1f, 1.0f}, DrawRole::Target);
      if (n.scored) snap.draw.sphere(n.sample, 2.0e-3, Rgba{0.15f, 0.35f, 1.0f, 1.0f}, DrawRole::Target);
    }
    rr.update(snap);
    render::OffscreenTarget target(w, h, 4);
    render::OrbitCamera orbit;
    orbit.target = rr.scene().focus;
    orbit.distance = rr.scene().extent * 2.6;
    render::RenderOptions ro;
    ro.title = "3D view at the end: target (red), sample (blue)";
    ro.opacity.clear();
    for (const auto& s : rr.scene().surfaces) {
      // the gland half-transparent and the rest faint, so that needles and markers show
      const bool gland = s.kind == render::OrganKind::Prostate;
      ro.opacity.push_back(gland ? 0.45f : std::min(s.colour.a, 0.18f));
    }
    target.bind();
    rr.render(render::preset_camera(render::View::Orbit, rr.scene(), &snap, orbit), w, h, ro);
    img.width = w;
    img.height = h;
    target.read_rgb(img.pixels);
  } catch (const render::RenderError& e) {
    note = std::string("3D view not drawn: no headless OpenGL here (") + e.what() + ")";
    img = RgbImage{};
  }
  return img;
}

RgbImage render_us(const Scene& scene, const Snapshot& snap, const us::ProbeView& probe, const Vec3& dir, int size) {
  const us::UltrasoundAnatomy anatomy = us::anatomy_for_scenario(scene.spec, *scene.model);
  us::UltrasoundSettings set = us::settings_for_probe(*scene.spec.probe);
  set.width = set.height = size;
  us::UltrasoundScene sc;
  us::scene_from_snapshot(snap, probe, sc);
  const bool along = std::abs(dir.normalized().dot(probe.axis)) > 0.985;  // within 10 deg: template needles
  us::PlaneImager im(anatomy, set, along ? us::PlaneKind::Transverse : us::PlaneKind::Sagittal);
  const us::UsImage& g = im.render(sc);
  RgbImage out;
  out.width = g.width;
  out.height = g.height;
  out.pixels.resize(static_cast<size_t>(g.width) * g.height * 3);
  for (size_t i = 0; i < g.pixels.size(); ++i) out.pixels[3 * i] = out.pixels[3 * i + 1] = out.pixels[3 * i + 2] = g.pixels[i];
  return out;
}

}  // namespace ps::app
