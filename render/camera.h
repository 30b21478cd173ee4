// Cameras: the preset views a urologist asks for (anterior, lateral = sagittal from the
// patient's right, along the probe, side-on to the active needle at its tip) and a free orbit
// camera. World
// frame: patient RAS in metres (x patient right, y anterior, z superior).
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>

#include "engine/util/vec.h"

namespace ps {
struct Snapshot;
}

namespace ps::render {

struct RenderScene;
using Mat4f = Eigen::Matrix4f;

enum class View : uint8_t { Anterior, Lateral, Probe, Needle, Orbit };

// "3d" is the orbit camera at its default angle; std::nullopt for an unknown name.
std::optional<View> parse_view(const std::string& name);
const char* view_name(View v);

struct Camera {
  Vec3 eye = Vec3(0, 0.3, 0), target = Vec3::Zero(), up = Vec3::UnitZ();  // [m]
  double fov_y_deg = 35.0;
  double near_m = 0.005, far_m = 2.0;
  Mat4f view() const;
  Mat4f projection(double aspect) const;
};

// Free orbit about a target: yaw about +z (superior), pitch above the axial plane, distance.
struct OrbitCamera {
  Vec3 target = Vec3::Zero();
  double yaw_deg = 30.0, pitch_deg = 15.0, distance = 0.25;  // [deg], [m]
  void rotate(double dyaw_deg, double dpitch_deg);
  void zoom(double factor);                  // distance *= factor
  void pan(double dx_m, double dy_m);        // in the view plane [m]
  Camera camera() const;
};

// The preset for a view. Probe and Needle use the snapshot's tool read-outs (probe tip/axis,
// active needle tip/axis) and fall back to the lateral view when the scene has no such tool.
Camera preset_camera(View v, const RenderScene& scene, const Snapshot* snap, const OrbitCamera& orbit);

}  // namespace ps::render
