#include "igtl/poses.h"

#include <cmath>

#include "engine/ultrasound/from_simulation.h"

namespace ps::igtl {

std::string needle_device_name(const std::string& needle) { return (needle + "Tip").substr(0, 20); }

Matrix frame_matrix(const Vec3& o, const Vec3& x, const Vec3& y, const Vec3& z) {
  Matrix m{};
  for (int r = 0; r < 3; ++r) {
    m[r][0] = static_cast<float>(x[r]);
    m[r][1] = static_cast<float>(y[r]);
    m[r][2] = static_cast<float>(z[r]);
    m[r][3] = static_cast<float>(o[r] * 1e3);
  }
  m[3] = {0.f, 0.f, 0.f, 1.f};
  return m;
}

std::vector<NamedPose> instrument_poses(const Snapshot& s, const std::vector<std::string>& needle_names) {
  std::vector<NamedPose> out;
  us::ProbeView pv;
  if (us::probe_view_from_snapshot(s, pv)) {
    const Vec3 z = pv.axis.normalized();
    const Vec3 y = pv.anterior.normalized();
    out.push_back({kProbeName, frame_matrix(pv.tip_centre, y.cross(z), y, z)});
  }
  size_t k = 0;
  for (const DrawSphere& tip : s.draw.spheres) {
    if (tip.role != DrawRole::NeedleTip) continue;
    Vec3 z = Vec3::UnitZ();
    for (const DrawCapsule& c : s.draw.capsules)  // the shaft starts at the tip and runs back
      if (c.role == DrawRole::Needle && (c.a - tip.centre).norm() < 1e-9 && (c.b - c.a).norm() > 0) {
        z = (c.a - c.b).normalized();
        break;
      }
    Vec3 up = Vec3::UnitY();
    if (std::abs(up.dot(z)) > 0.9) up = Vec3::UnitX();
    const Vec3 x = up.cross(z).normalized();
    const std::string name = k < needle_names.size() ? needle_names[k] : "needle" + std::to_string(k + 1);
    out.push_back({needle_device_name(name), frame_matrix(tip.centre, x, z.cross(x), z)});
    ++k;
  }
  return out;
}

Matrix image_matrix(const us::PlaneImager& imager, const us::ProbeView& probe, int width, int height) {
  const us::PlaneFrame f = imager.frame(probe);
  const Vec3 i = f.right.normalized();
  const Vec3 j = (-f.up).normalized();  // rows top-down: away from the probe is up the screen
  const Vec3 centre = imager.pixel_to_world(probe, 0.5 * (width - 1), 0.5 * (height - 1));
  return frame_matrix(centre, i, j, i.cross(j));
}

}  // namespace ps::igtl
