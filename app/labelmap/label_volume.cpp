#include "app/labelmap/label_volume.h"

#include <cmath>
#include <string>

#include "engine/util/error.h"

namespace ps::labelmap {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

LabelVolume read_label_volume_nrrd(const std::string& path);    // label_nrrd.cpp
LabelVolume read_label_volume_nifti(const std::string& path);   // label_nifti.cpp

LabelVolume read_label_volume(const std::string& path) {
  if (ends_with(path, ".nrrd") || ends_with(path, ".nhdr")) return read_label_volume_nrrd(path);
  if (ends_with(path, ".nii") || ends_with(path, ".nii.gz")) return read_label_volume_nifti(path);
  throw InputError(path, 0, "--from-labels", "not a label map file: expected .nrrd, .nhdr, .nii or .nii.gz");
}

void check_spacing(const LabelVolume& v, const std::string& field) {
  const char* axes = "ijk";
  for (int a = 0; a < 3; ++a)
    if (v.size[a] < 1) throw InputError(v.file, 0, "sizes", std::string("axis ") + axes[a] + " has no voxels");
  double lo = 1e300, hi = 0.0;
  for (int a = 0; a < 3; ++a) {
    const Vec3 e = v.index_to_ras_m.col(a);
    const double len_mm = e.norm() * 1e3;
    if (!e.allFinite() || !std::isfinite(len_mm))
      throw InputError(v.file, 0, field, std::string("voxel edge along ") + axes[a] + " is not a finite number");
    if (len_mm <= 0.0)
      throw InputError(v.file, 0, field, std::string("voxel edge along ") + axes[a] + " is zero or negative");
    if (len_mm > kMaxVoxelEdgeMm) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "voxel edge along %c is %.3g mm, over the %.3g mm limit (docs/anatomy.md)", axes[a], len_mm, kMaxVoxelEdgeMm);
      throw InputError(v.file, 0, field, buf);
    }
    lo = std::min(lo, len_mm);
    hi = std::max(hi, len_mm);
  }
  if (hi > kMaxVoxelAnisotropy * lo) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "voxel edges %.3g to %.3g mm: anisotropy %.3g over the limit of %.3g (docs/anatomy.md)", lo, hi, hi / lo, kMaxVoxelAnisotropy);
    throw InputError(v.file, 0, field, buf);
  }
  if (std::abs(v.index_to_ras_m.determinant()) <= 1e-6 * std::pow(lo * 1e-3, 3))
    throw InputError(v.file, 0, field, "voxel edges are linearly dependent (a flat voxel)");
  if (!v.origin_ras_m.allFinite()) throw InputError(v.file, 0, field, "origin is not a finite point");
}

}  // namespace ps::labelmap
