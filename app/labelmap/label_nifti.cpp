// NIfTI label maps through nifti2 (libnifti2-dev, reads NIfTI-1 and -2, .nii and .nii.gz): what
// 3D Slicer writes for a segmentation exported as a labelmap volume.
#include <nifti2_io.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "app/labelmap/label_volume.h"
#include "engine/util/error.h"

namespace ps::labelmap {

namespace {

struct NimDeleter {
  void operator()(nifti_image* n) const { nifti_image_free(n); }
};
using NimPtr = std::unique_ptr<nifti_image, NimDeleter>;

template <typename T>
void copy_labels(const void* data, size_t count, std::vector<int32_t>& out, const std::string& path) {
  const T* p = static_cast<const T*>(data);
  out.resize(count);
  for (size_t n = 0; n < count; ++n) {
    const double x = static_cast<double>(p[n]);
    if (!(x == std::floor(x)) || x < -2147483648.0 || x > 2147483647.0)
      throw InputError(path, 0, "datatype", "voxel " + std::to_string(n) + " holds " + std::to_string(x) + ", not an integer label");
    out[n] = static_cast<int32_t>(x);
  }
}

}  // namespace

LabelVolume read_label_volume_nifti(const std::string& path) {
  nifti_set_debug_level(0);
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "", "cannot read NIfTI: no such file");
  // The raw header's pixdim first: the library replaces a zero or negative voxel size by 1.
  int version = 0;
  void* raw = nifti_read_header(path.c_str(), &version, 1);
  if (!raw) throw InputError(path, 0, "", "cannot read NIfTI: not a valid NIfTI-1 or NIfTI-2 header");
  double pixdim[4] = {};
  int sform_code = 0;
  if (version == 2) {
    const auto* h = static_cast<const nifti_2_header*>(raw);
    for (int a = 1; a < 4; ++a) pixdim[a] = h->pixdim[a];
    sform_code = h->sform_code;
  } else {
    const auto* h = static_cast<const nifti_1_header*>(raw);
    for (int a = 1; a < 4; ++a) pixdim[a] = h->pixdim[a];
    sform_code = h->sform_code;
  }
  std::free(raw);
  if (sform_code <= 0)
    for (int a = 1; a < 4; ++a)
      if (!std::isfinite(pixdim[a]) || pixdim[a] <= 0.0)
        throw InputError(path, 0, "pixdim", "voxel size along " + std::string(1, "ijk"[a - 1]) + " is " + std::to_string(pixdim[a]) + " (must be a positive number)");

  NimPtr nim(nifti_image_read(path.c_str(), 1));
  if (!nim || !nim->data) throw InputError(path, 0, "", "cannot read NIfTI image data");
  if (nim->dim[0] < 3 || (nim->dim[0] > 3 && nim->nt * nim->nu * nim->nv * nim->nw > 1))
    throw InputError(path, 0, "dim", "a label map has 3 axes, this file has " + std::to_string(nim->dim[0]));
  LabelVolume v;
  v.file = path;
  v.size = {static_cast<int>(nim->nx), static_cast<int>(nim->ny), static_cast<int>(nim->nz)};
  // sform when set (Slicer writes it), else qform, else the voxel sizes alone
  const nifti_dmat44* m = nim->sform_code > 0 ? &nim->sto_xyz : nim->qform_code > 0 ? &nim->qto_xyz : nullptr;
  const std::string field = nim->sform_code > 0 ? "srow_x/srow_y/srow_z (sform)" : "pixdim";
  if (m) {
    for (int r = 0; r < 3; ++r) {
      for (int a = 0; a < 3; ++a) v.index_to_ras_m(r, a) = m->m[r][a] * 1e-3;
      v.origin_ras_m[r] = m->m[r][3] * 1e-3;
    }
  } else {
    v.index_to_ras_m = Vec3(nim->dx, nim->dy, nim->dz).asDiagonal();
    v.index_to_ras_m *= 1e-3;
  }
  check_spacing(v, field);
  const size_t count = static_cast<size_t>(v.size[0]) * v.size[1] * v.size[2];
  switch (nim->datatype) {
    case DT_UINT8: copy_labels<uint8_t>(nim->data, count, v.labels, path); break;
    case DT_INT8: copy_labels<int8_t>(nim->data, count, v.labels, path); break;
    case DT_INT16: copy_labels<int16_t>(nim->data, count, v.labels, path); break;
    case DT_UINT16: copy_labels<uint16_t>(nim->data, count, v.labels, path); break;
    case DT_INT32: copy_labels<int32_t>(nim->data, count, v.labels, path); break;
    case DT_UINT32: copy_labels<uint32_t>(nim->data, count, v.labels, path); break;
    case DT_FLOAT32: copy_labels<float>(nim->data, count, v.labels, path); break;
    case DT_FLOAT64: copy_labels<double>(nim->data, count, v.labels, path); break;
    default: throw InputError(path, 0, "datatype", "unsupported voxel type " + std::to_string(nim->datatype) + " for labels");
  }
  return v;
}

void write_label_volume_nifti(const std::string& path, const LabelVolume& v) {
  const int64_t dims[8] = {3, v.size[0], v.size[1], v.size[2], 1, 1, 1, 1};
  NimPtr nim(nifti_make_new_nim(dims, DT_UINT16, 1));
  if (!nim) throw std::runtime_error(path + ": cannot make a NIfTI image");
  auto* data = static_cast<uint16_t*>(nim->data);
  for (size_t n = 0; n < v.labels.size(); ++n) data[n] = static_cast<uint16_t>(v.labels[n]);
  const Vec3 s = v.spacing_m() * 1e3;
  nim->dx = nim->pixdim[1] = s.x();
  nim->dy = nim->pixdim[2] = s.y();
  nim->dz = nim->pixdim[3] = s.z();
  nim->xyz_units = NIFTI_UNITS_MM;
  nifti_dmat44 m{};
  for (int r = 0; r < 3; ++r) {
    for (int a = 0; a < 3; ++a) m.m[r][a] = v.index_to_ras_m(r, a) * 1e3;
    m.m[r][3] = v.origin_ras_m[r] * 1e3;
  }
  m.m[3][3] = 1.0;
  nim->sform_code = nim->qform_code = NIFTI_XFORM_SCANNER_ANAT;
  nim->sto_xyz = m;
  nim->qto_xyz = m;
  double dx, dy, dz;
  nifti_dmat44_to_quatern(m, &nim->quatern_b, &nim->quatern_c, &nim->quatern_d, &nim->qoffset_x, &nim->qoffset_y,
                          &nim->qoffset_z, &dx, &dy, &dz, &nim->qfac);
  nim->nifti_type = NIFTI_FTYPE_NIFTI1_1;
  const std::filesystem::path p(path);
  const std::string tmp = (p.parent_path() / (".tmp" + std::to_string(::getpid()) + "_" + p.filename().string())).string();
  if (nifti_set_filenames(nim.get(), tmp.c_str(), 0, 1)) throw std::runtime_error(path + ": bad NIfTI file name");
  nifti_image_write(nim.get());
  std::error_code ec;
  if (!std::filesystem::is_regular_file(tmp)) throw std::runtime_error(path + ": cannot write NIfTI");
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": " + ec.message());
  }
}

}  // namespace ps::labelmap
