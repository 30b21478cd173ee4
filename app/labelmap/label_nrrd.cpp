// NRRD label maps through Teem's nrrd library (libteem-dev): what 3D Slicer writes for a
// segmentation exported as a labelmap (.nrrd, gzip, "space: left-posterior-superior").
#include <teem/nrrd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "app/labelmap/label_volume.h"
#include "engine/util/error.h"

namespace ps::labelmap {

namespace {

struct NrrdDeleter {
  void operator()(Nrrd* n) const { nrrdNuke(n); }
};
using NrrdPtr = std::unique_ptr<Nrrd, NrrdDeleter>;

// Teem's error stack for the nrrd library, one line.
std::string teem_error() {
  char* e = biffGetDone(NRRD);
  std::string s = e ? e : "unknown error";
  std::free(e);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s;
}

}  // namespace

LabelVolume read_label_volume_nrrd(const std::string& path) {
  NrrdPtr n(nrrdNew());
  if (nrrdLoad(n.get(), path.c_str(), nullptr)) throw InputError(path, 0, "", "cannot read NRRD: " + teem_error());
  LabelVolume v;
  v.file = path;
  // Slicer's .seg.nrrd may carry a leading list axis of one layer: use the three spatial axes.
  unsigned first = 0;
  if (n->dim == 4 && n->axis[0].size == 1) first = 1;
  else if (n->dim != 3)
    throw InputError(path, 0, "dimension", "a label map has 3 axes, this file has " + std::to_string(n->dim));
  switch (n->type) {
    case nrrdTypeChar: case nrrdTypeUChar: case nrrdTypeShort: case nrrdTypeUShort: case nrrdTypeInt: case nrrdTypeUInt: break;
    default:
      throw InputError(path, 0, "type", std::string("labels must be integers of at most 32 bits, not ") + airEnumStr(nrrdType, n->type));
  }
  for (int a = 0; a < 3; ++a) v.size[a] = static_cast<int>(n->axis[first + a].size);

  // RAS from the space directions (LPS and LAS flipped), or from per-axis spacings when the file
  // has no space.
  double flip[3] = {1, 1, 1};
  std::string field = "space directions";
  if (n->space == nrrdSpaceLeftPosteriorSuperior || n->space == nrrdSpaceScannerXYZ) flip[0] = flip[1] = -1;
  else if (n->space == nrrdSpaceLeftAnteriorSuperior) flip[0] = -1;
  else if (n->space == nrrdSpaceRightAnteriorSuperior || n->space == nrrdSpace3DRightHanded) {}
  else if (n->space != nrrdSpaceUnknown)
    throw InputError(path, 0, "space", std::string("unsupported space '") + airEnumStr(nrrdSpace, n->space) + "' (use RAS or LPS)");
  if (n->space != nrrdSpaceUnknown) {
    if (n->spaceDim != 3) throw InputError(path, 0, "space dimension", "must be 3");
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) v.index_to_ras_m(r, a) = flip[r] * n->axis[first + a].spaceDirection[r] * 1e-3;
    for (int r = 0; r < 3; ++r) v.origin_ras_m[r] = flip[r] * n->spaceOrigin[r] * 1e-3;
    if (!v.origin_ras_m.allFinite()) v.origin_ras_m.setZero();   // "space origin" is optional
  } else {
    field = "spacings";
    v.index_to_ras_m.setZero();
    for (int a = 0; a < 3; ++a) {
      const double sp = n->axis[first + a].spacing;
      if (!std::isfinite(sp) || sp <= 0.0)
        throw InputError(path, 0, field, std::string("voxel size along ") + "ijk"[a] + " is " + std::to_string(sp) + " (must be a positive number)");
      v.index_to_ras_m(a, a) = sp * 1e-3;
    }
  }
  check_spacing(v, field);

  NrrdPtr as_int(nrrdNew());
  if (nrrdConvert(as_int.get(), n.get(), nrrdTypeInt)) throw InputError(path, 0, "", "cannot convert the labels: " + teem_error());
  const size_t count = static_cast<size_t>(v.size[0]) * v.size[1] * v.size[2];
  const int* data = static_cast<const int*>(as_int->data);
  v.labels.assign(data, data + count);
  return v;
}

void write_label_volume_nrrd(const std::string& path, const LabelVolume& v) {
  std::vector<unsigned short> data(v.labels.begin(), v.labels.end());
  const size_t sizes[3] = {static_cast<size_t>(v.size[0]), static_cast<size_t>(v.size[1]), static_cast<size_t>(v.size[2])};
  // nrrdNix, not nrrdNuke, for a wrapped buffer the vector owns
  std::unique_ptr<Nrrd, Nrrd* (*)(Nrrd*)> w(nrrdNew(), nrrdNix);
  if (nrrdWrap_nva(w.get(), data.data(), nrrdTypeUShort, 3, sizes)) throw std::runtime_error(path + ": " + teem_error());
  nrrdSpaceSet(w.get(), nrrdSpaceLeftPosteriorSuperior);
  const double lps[3] = {-1, -1, 1};
  double origin[NRRD_SPACE_DIM_MAX] = {};
  for (int r = 0; r < 3; ++r) origin[r] = lps[r] * v.origin_ras_m[r] * 1e3;
  nrrdSpaceOriginSet(w.get(), origin);
  double dirs[NRRD_DIM_MAX][NRRD_SPACE_DIM_MAX] = {};
  for (int a = 0; a < 3; ++a)
    for (int r = 0; r < 3; ++r) dirs[a][r] = lps[r] * v.index_to_ras_m(r, a) * 1e3;
  nrrdAxisInfoSet_nva(w.get(), nrrdAxisInfoSpaceDirection, dirs);
  int kinds[NRRD_DIM_MAX] = {nrrdKindDomain, nrrdKindDomain, nrrdKindDomain};
  nrrdAxisInfoSet_nva(w.get(), nrrdAxisInfoKind, kinds);
  std::unique_ptr<NrrdIoState, NrrdIoState* (*)(NrrdIoState*)> nio(nrrdIoStateNew(), nrrdIoStateNix);
  if (nrrdEncodingGzip->available()) nio->encoding = nrrdEncodingGzip;
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + ".nrrd";
  if (nrrdSave(tmp.c_str(), w.get(), nio.get())) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot write NRRD: " + teem_error());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": " + ec.message());
  }
}

}  // namespace ps::labelmap
