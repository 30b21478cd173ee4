#include "app/editor/view_drag.h"

#include <algorithm>
#include <cmath>

namespace ps::editor {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

std::vector<Handle> handles(const EditorCommands& c) {
  std::vector<Handle> out;
  for (const RegionView& r : c.regions()) out.push_back({Handle::Region, r.tag, r.center_mm, r.size_mm.maxCoeff(), r.lesion});
  if (c.spec())
    for (const NeedleSpec& n : c.spec()->needles.needles)
      if (n.target) out.push_back({Handle::Target, n.name, 1e3 * *n.target, 1.5, false});
  return out;
}

bool project(const render::Camera& cam, const ViewRect& v, const Vec3& x, float& px, float& py, float* px_per_m) {
  const Eigen::Matrix4f m = cam.projection(v.w / v.h) * cam.view();
  const Eigen::Vector4f c = m * Eigen::Vector4f(static_cast<float>(x.x()), static_cast<float>(x.y()), static_cast<float>(x.z()), 1.0f);
  if (c.w() <= 1e-6f) return false;
  px = v.x + (c.x() / c.w() * 0.5f + 0.5f) * v.w;
  py = v.y + (1.0f - (c.y() / c.w() * 0.5f + 0.5f)) * v.h;
  if (px_per_m) *px_per_m = static_cast<float>(v.h / (2.0 * c.w() * std::tan(cam.fov_y_deg * kPi / 360.0)));
  return true;
}

Vec3 drag_move_mm(const render::Camera& cam, const ViewRect& v, const Vec3& at_mm, float dx, float dy) {
  // camera right and up: the first two rows of the view matrix
  const Eigen::Matrix4f m = cam.view();
  const Vec3 right(m(0, 0), m(0, 1), m(0, 2)), up(m(1, 0), m(1, 1), m(1, 2));
  // depth along the view axis (not the distance to the eye): what the projection divides by
  const Vec3 fwd = (cam.target - cam.eye).normalized();
  const double depth = (1e-3 * at_mm - cam.eye).dot(fwd);
  const double m_per_px = 2.0 * depth * std::tan(cam.fov_y_deg * kPi / 360.0) / v.h;
  return 1e3 * m_per_px * (static_cast<double>(dx) * right - static_cast<double>(dy) * up);
}

bool ViewDrag::press(const EditorCommands& c, const render::Camera& cam, const ViewRect& v, float mx, float my) {
  float best = kPickPx;
  dragging_ = false;
  offset_mm_ = Vec3::Zero();
  for (const Handle& h : handles(c)) {
    float px = 0, py = 0, ppm = 0;
    if (!project(cam, v, 1e-3 * h.pos_mm, px, py, &ppm)) continue;
    const float r = std::max(6.0f, static_cast<float>(1e-3 * h.radius_mm) * ppm);
    const float d = std::hypot(px - mx, py - my);
    if (d < std::max(best, r)) {
      best = d;
      selected_ = h.name;
      kind_ = h.kind;
      dragging_ = true;
    }
  }
  return dragging_;
}

void ViewDrag::move(const EditorCommands& c, const render::Camera& cam, const ViewRect& v, float dx, float dy) {
  if (!dragging_) return;
  for (const Handle& h : handles(c))
    if (h.name == selected_ && h.kind == kind_) offset_mm_ += drag_move_mm(cam, v, h.pos_mm + offset_mm_, dx, dy);
}

EditResult ViewDrag::release(EditorCommands& c, FieldErrors& errs) {
  EditResult r;
  const bool was = dragging_;
  dragging_ = false;
  const Vec3 off = offset_mm_;
  offset_mm_ = Vec3::Zero();
  if (!was || off.norm() <= 0.05) return r;
  for (const Handle& h : handles(c)) {
    if (h.name != selected_ || h.kind != kind_) continue;
    const Vec3 to = (h.pos_mm + off).array().round().matrix();  // whole mm
    if (h.kind == Handle::Region) {
      r = c.move_region(h.name, to);
      errs.note("tags[" + h.name + "]", r);
    } else {
      r = c.set_needle_target(h.name, to);
      errs.note("needles.instruments[" + h.name + "].target_mm", r);
    }
    return r;
  }
  return r;
}

}  // namespace ps::editor
