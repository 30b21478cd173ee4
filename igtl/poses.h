// What the OpenIGTLink server (igtl/server.h) sends, as plain geometry from a Snapshot: the
// instruments' frames and the TRUS planes' image-to-scene matrices. Millimetres, the scene frame
// (patient RAS, as Slicer's). No sockets here (tested without a network).
//   Probe        origin: the tip-hemisphere centre; z: the probe axis (insertion direction);
//                y: anterior (the side the arrays look to); x = y cross z.
//   <needle>Tip  origin: the needle tip; z: its direction of insertion; x, y: completed with
//                the scene's y (anterior) as "up" where it is not along the needle.
//   US_Transverse, US_Sagittal: IMAGE i along the screen's right, j down the rows, k = i x j;
//                origin: the centre of the image (OpenIGTLink's convention), spacing: the pixel.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "engine/contract/snapshot.h"
#include "engine/ultrasound/imager.h"

namespace ps::igtl {

using Matrix = std::array<std::array<float, 4>, 4>;   // row-major, last row 0 0 0 1

struct NamedPose {
  std::string name;                 // OpenIGTLink device name (at most 20 characters)
  Matrix m{};
};

inline constexpr const char* kProbeName = "Probe";
inline constexpr const char* kTransverseName = "US_Transverse";
inline constexpr const char* kSagittalName = "US_Sagittal";
// "<needle>Tip", cut to OpenIGTLink's 20-character device names
std::string needle_device_name(const std::string& needle);

// The frame with origin `o` [m] and unit axes x, y, z, as a matrix in mm.
Matrix frame_matrix(const Vec3& o, const Vec3& x, const Vec3& y, const Vec3& z);

// The probe (when the snapshot draws one) and every needle tip drawn in it (DrawRole::NeedleTip,
// in the scene's needle order: `needle_names`).
std::vector<NamedPose> instrument_poses(const Snapshot& s, const std::vector<std::string>& needle_names);

// Image-to-scene matrix of a plane for a probe pose: the columns are the unit i, j, k axes, the
// translation the image centre [mm] (OpenIGTLink IMAGE origin).
Matrix image_matrix(const us::PlaneImager& imager, const us::ProbeView& probe, int width, int height);

}  // namespace ps::igtl
