#include "engine/ultrasound/from_simulation.h"

#include <cmath>
#include <filesystem>

namespace ps::us {

ProbeView probe_view(const ProbeFrame& f, double radius) {
  ProbeView v;
  v.tip_centre = f.capsule.tip;
  v.axis = f.rot.col(0);
  v.anterior = f.rot.col(1);
  v.lateral = f.rot.col(2);
  v.radius = radius;
  return v;
}

void scene_from_state(const State& s, const ProbeTool* probe, const NeedleTool* needles, const SceneOptions& opt,
                      UltrasoundScene& sc) {
  const size_t n = s.x.size();
  sc.x_storage.resize(3 * n);
  for (size_t p = 0; p < n; ++p)
    for (int d = 0; d < 3; ++d) sc.x_storage[3 * p + d] = static_cast<float>(s.x[p][d]);
  sc.x = sc.x_storage.data();
  sc.particle_count = static_cast<int>(n);
  sc.rods.clear();
  sc.overlays.clear();
  if (probe) {
    sc.probe = probe_view(probe->frame(), probe->spec().radius);
    if (opt.guide) {
      const NeedlePath g = probe->biopsy_guide();
      sc.overlays.push_back({OverlayLine::Guide, g.entry, g.direction});
    }
    if (opt.grid)
      for (int c = 0; c < probe->spec().template_cols; ++c)
        for (int r = 0; r < probe->spec().template_rows; ++r) {
          const NeedlePath h = probe->template_hole(c, r);
          sc.overlays.push_back({OverlayLine::TemplateHole, h.entry, h.direction});
        }
  }
  if (needles) {
    for (int i = 0; i < needles->count(); ++i) {
      const NeedleReadout& r = needles->readout(i);
      Rod rod;
      rod.a = r.tip;
      rod.b = r.tip - needles->spec(i).length * r.direction;
      rod.radius = 0.5 * needles->spec(i).diameter;
      sc.rods.push_back(rod);
    }
    for (const SeedReport& sd : needles->seeds()) {
      if (!sd.deposited) continue;
      const Vec3 d = needles->readout(sd.needle).direction;
      Rod rod;
      rod.a = sd.current + 0.5 * kSeedLength * d;
      rod.b = sd.current - 0.5 * kSeedLength * d;
      rod.radius = kSeedRadius;
      rod.reflect = 10.0f;
      rod.reverb = 0.45f;
      rod.shadow = 0.8f;
      sc.rods.push_back(rod);
    }
  }
}

bool probe_view_from_snapshot(const Snapshot& snap, ProbeView& v) {
  const DrawCapsule* body = nullptr;
  const DrawCapsule* guide = nullptr;
  for (const DrawCapsule& c : snap.draw.capsules) {
    if (c.role == DrawRole::Probe && !body) body = &c;
    if (c.role == DrawRole::Guide && !guide) guide = &c;
  }
  if (!body || !((body->b - body->a).norm() > 1e-9)) return false;
  v.tip_centre = body->b;
  v.axis = (body->b - body->a).normalized();
  v.radius = body->radius;
  Vec3 ant = Vec3::UnitY();
  if (guide) ant = guide->b - body->b;  // guide exit: radius * anterior (+ along the axis)
  ant -= ant.dot(v.axis) * v.axis;
  if (!(ant.norm() > 1e-9)) {  // guide on the axis or axis along +y: any perpendicular
    ant = Vec3::UnitZ() - Vec3::UnitZ().dot(v.axis) * v.axis;
    if (!(ant.norm() > 1e-9)) ant = Vec3::UnitX() - Vec3::UnitX().dot(v.axis) * v.axis;
  }
  v.anterior = ant.normalized();
  v.lateral = v.axis.cross(v.anterior);
  return true;
}

void scene_from_snapshot(const Snapshot& snap, const ProbeView& probe, UltrasoundScene& sc) {
  sc.x = snap.x.data();
  sc.particle_count = static_cast<int>(snap.x.size() / 3);
  sc.probe = probe;
  sc.rods.clear();
  sc.overlays.clear();
  for (const DrawCapsule& c : snap.draw.capsules) {
    if (c.role != DrawRole::Needle && c.role != DrawRole::Seed) continue;
    Rod rod;
    rod.a = c.a;
    rod.b = c.b;
    rod.radius = c.radius;
    if (c.role == DrawRole::Seed) rod.reflect = 10.0f, rod.reverb = 0.45f, rod.shadow = 0.8f;
    sc.rods.push_back(rod);
  }
  for (const DrawSphere& s : snap.draw.spheres) {
    if (s.role != DrawRole::Seed) continue;
    Rod rod;  // orientation unknown: a short rod along the probe axis
    rod.a = s.centre + 0.5 * kSeedLength * probe.axis;
    rod.b = s.centre - 0.5 * kSeedLength * probe.axis;
    rod.radius = kSeedRadius;
    rod.reflect = 10.0f, rod.reverb = 0.45f, rod.shadow = 0.8f;
    sc.rods.push_back(rod);
  }
  // the guide's planned path is drawn as dashes along one line: one overlay line for all of them
  for (const DrawSegment& s : snap.draw.segments) {
    if (s.role != DrawRole::Guide || !((s.b - s.a).norm() > 0)) continue;
    const Vec3 d = (s.b - s.a).normalized();
    bool same = false;
    for (const OverlayLine& o : sc.overlays)
      if (o.kind == OverlayLine::Guide && std::abs(o.direction.dot(d)) > 0.9999 &&
          ((s.a - o.entry) - (s.a - o.entry).dot(o.direction) * o.direction).norm() < 1e-5)
        same = true;
    if (!same) sc.overlays.push_back({OverlayLine::Guide, s.a, d});
  }
  // template holes (the stepper's grid: spheres at the hole entries, lines parallel to the probe axis)
  for (const DrawSphere& s : snap.draw.spheres)
    if (s.role == DrawRole::TemplateGrid) sc.overlays.push_back({OverlayLine::TemplateHole, s.centre, probe.axis});
}

UltrasoundAnatomy anatomy_for_scenario(const ScenarioSpec& spec, const Model& model) {
  AnatomyOptions opt;
  for (size_t i = 0; i < spec.components.size() && i < model.components.size(); ++i) {
    const ComponentSpec& c = spec.components[i];  // compile keeps the file's order of components
    if (c.shape.kind != ShapeSpec::Mesh || model.components[i].role != Role::Prostate) continue;
    const MeshShapeSpec& m = c.shape.mesh;
    // only for an untransformed mesh: the foci are in the mesh file's own frame
    const std::filesystem::path k = std::filesystem::path(m.file).parent_path() / "calcifications.csv";
    if (std::filesystem::exists(k) && m.rotate_deg.isZero() && m.scale.isOnes())
      opt.calcifications = read_calcifications_csv(k.string(), m.unit_scale, m.translate);
  }
  opt.display_meshes = anatomy::display_meshes_for_scenario(spec, model);
  return build_anatomy(model, opt);
}

}  // namespace ps::us
