// A label map as 3D Slicer exports a segmentation (NRRD .nrrd/.seg.nrrd/.nhdr, NIfTI .nii/.nii.gz):
// one integer label per voxel and the voxel -> patient RAS transform. Read and written with the
// Debian libraries made for each format: Teem's nrrd (libteem-dev) and nifti2 (libnifti2-dev).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/util/vec.h"

namespace ps::labelmap {

// Largest voxel edge and largest ratio of voxel edges accepted [mm, -]. Organ surfaces are
// rebuilt from the voxels: a 5 mm voxel is already coarser than the rectal wall and the gaps
// between organs, and typical prostate MRI segmentations (0.5 x 0.5 x 3.6 mm) stay under a
// ratio of 10.
inline constexpr double kMaxVoxelEdgeMm = 5.0;
inline constexpr double kMaxVoxelAnisotropy = 10.0;

struct LabelVolume {
  std::array<int, 3> size{0, 0, 0};            // voxels along i, j, k
  Mat3 index_to_ras_m = Mat3::Identity();      // columns: voxel edge vectors i, j, k in RAS [m]
  Vec3 origin_ras_m = Vec3::Zero();            // centre of voxel (0,0,0) in RAS [m]
  std::vector<int32_t> labels;                 // i fastest, then j, then k
  std::string file;                            // where it was read from (for errors)

  size_t index(int i, int j, int k) const {
    return static_cast<size_t>(i) + static_cast<size_t>(size[0]) * (static_cast<size_t>(j) + static_cast<size_t>(size[1]) * k);
  }
  Vec3 ras_m(double i, double j, double k) const { return origin_ras_m + index_to_ras_m * Vec3(i, j, k); }
  Vec3 spacing_m() const {
    return Vec3(index_to_ras_m.col(0).norm(), index_to_ras_m.col(1).norm(), index_to_ras_m.col(2).norm());
  }
};

// Reads a label map, chosen by the file name: .nrrd / .nhdr (Teem) or .nii / .nii.gz (nifti2).
// NRRD in a left-posterior-superior space (Slicer's) is turned into RAS. Throws InputError naming
// the file and the field for an unreadable file, a non-integer or non-3D image, or a voxel edge
// that is zero, negative, not finite, over kMaxVoxelEdgeMm or over kMaxVoxelAnisotropy times
// the shortest.
LabelVolume read_label_volume(const std::string& path);

// Writes a label map (uint16 voxels, gzip-compressed) as Slicer would: NRRD in
// left-posterior-superior space, NIfTI with an sform in RAS. Throws std::runtime_error naming the
// path on failure. The writers are what the tests use to make label maps of known shapes.
void write_label_volume_nrrd(const std::string& path, const LabelVolume& v);
void write_label_volume_nifti(const std::string& path, const LabelVolume& v);

// Checks the voxel edges (see read_label_volume); `field` names the header field they came from.
void check_spacing(const LabelVolume& v, const std::string& field);

}  // namespace ps::labelmap
