#include "render/camera.h"

#include <cmath>

#include "engine/contract/snapshot.h"
#include "render/render_scene.h"

namespace ps::render {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

std::optional<View> parse_view(const std::string& n) {
  if (n == "3d" || n == "orbit") return View::Orbit;
  if (n == "anterior") return View::Anterior;
  if (n == "lateral") return View::Lateral;
  if (n == "probe") return View::Probe;
  if (n == "needle") return View::Needle;
  return std::nullopt;
}

const char* view_name(View v) {
  switch (v) {
    case View::Anterior: return "anterior";
    case View::Lateral: return "lateral";
    case View::Probe: return "probe";
    case View::Needle: return "needle";
    case View::Orbit: return "3d";
  }
  return "?";
}

Mat4f Camera::view() const {
  const Eigen::Vector3f f = (target - eye).normalized().cast<float>();
  const Eigen::Vector3f s = f.cross(up.cast<float>()).normalized();
  const Eigen::Vector3f u = s.cross(f);
  Mat4f m = Mat4f::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  const Eigen::Vector3f e = eye.cast<float>();
  m(0, 3) = -s.dot(e);
  m(1, 3) = -u.dot(e);
  m(2, 3) = f.dot(e);
  return m;
}

Mat4f Camera::projection(double aspect) const {
  const float t = static_cast<float>(1.0 / std::tan(0.5 * fov_y_deg * kPi / 180.0));
  const float n = static_cast<float>(near_m), f = static_cast<float>(far_m);
  Mat4f p = Mat4f::Zero();
  p(0, 0) = t / static_cast<float>(aspect);
  p(1, 1) = t;
  p(2, 2) = (f + n) / (n - f);
  p(2, 3) = 2 * f * n / (n - f);
  p(3, 2) = -1;
  return p;
}

void OrbitCamera::rotate(double dy, double dp) {
  yaw_deg = std::fmod(yaw_deg + dy, 360.0);
  pitch_deg = std::clamp(pitch_deg + dp, -89.0, 89.0);
}
void OrbitCamera::zoom(double f) { distance = std::clamp(distance * f, 0.02, 2.0); }
void OrbitCamera::pan(double dx, double dy) {
  const Camera c = camera();
  const Vec3 fwd = (c.target - c.eye).normalized();
  const Vec3 right = fwd.cross(c.up).normalized();
  const Vec3 up = right.cross(fwd);
  target += dx * right + dy * up;
}

Camera OrbitCamera::camera() const {
  const double y = yaw_deg * kPi / 180.0, p = pitch_deg * kPi / 180.0;
  Camera c;
  c.target = target;
  c.eye = target + distance * Vec3(std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), std::sin(p));
  c.up = Vec3::UnitZ();
  c.near_m = std::max(0.002, distance * 0.02);
  c.far_m = distance * 20.0;
  return c;
}

Camera preset_camera(View v, const RenderScene& sc, const Snapshot* snap, const OrbitCamera& orbit) {
  // distance that frames `extent` at the field of view, with a margin
  const double dist = sc.extent / std::tan(0.5 * 35.0 * kPi / 180.0) * 1.05;
  Camera c;
  c.target = sc.focus;
  c.near_m = std::max(0.002, dist * 0.02);
  c.far_m = dist * 20.0;
  const ToolReadout* probe = nullptr;
  const ToolReadout* needle = nullptr;
  if (snap)
    for (const auto& t : snap->tools) {
      if ((t.carries & kCarriesImaging) && !probe) probe = &t;
      if ((t.carries & kCarriesInsertion) && (!needle || (t.active && !needle->active))) needle = &t;
    }
  if (v == View::Probe && !probe) v = View::Lateral;
  if (v == View::Needle && !needle) v = View::Lateral;
  switch (v) {
    case View::Anterior:  // from the front, patient's right on the viewer's left
      c.eye = sc.focus + Vec3(0, dist, 0);
      c.up = Vec3::UnitZ();
      break;
    case View::Lateral:  // sagittal, from the patient's right: anterior to the right
      c.eye = sc.focus + Vec3(dist, 0, 0);
      c.up = Vec3::UnitZ();
      break;
    case View::Probe: {  // from behind the probe's handle, anterior up
      const Vec3 a = probe->axis.normalized();
      Vec3 up = Vec3::UnitY() - Vec3::UnitY().dot(a) * a;
      if (up.norm() < 1e-6) up = Vec3::UnitZ();
      c.eye = probe->tip - 0.16 * a + 0.035 * up.normalized();
      c.target = probe->tip + 0.03 * a + 0.02 * up.normalized();
      c.up = up.normalized();
      c.near_m = 0.005;
      c.far_m = 1.0;
      break;
    }
    case View::Needle: {  // side-on to the needle from the patient's right, zoomed on the tip
      const Vec3 a = needle->axis.normalized();
      Vec3 side = Vec3::UnitX() - Vec3::UnitX().dot(a) * a;
      if (side.norm() < 1e-3) side = Vec3::UnitY() - Vec3::UnitY().dot(a) * a;
      side.normalize();
      Vec3 up = Vec3::UnitZ() - Vec3::UnitZ().dot(a) * a - Vec3::UnitZ().dot(side) * side;
      if (up.norm() < 1e-3) up = a.cross(side);
      c.target = needle->tip - 0.01 * a;
      c.eye = c.target + 0.14 * side;
      c.up = up.normalized();
      c.near_m = 0.01;
      c.far_m = 1.0;
      break;
    }
    case View::Orbit:
      return orbit.camera();
  }
  return c;
}

}  // namespace ps::render
