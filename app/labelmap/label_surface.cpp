#include "app/labelmap/label_surface.h"

#include <teem/gage.h>
#include <teem/limn.h>
#include <teem/nrrd.h>
#include <teem/seek.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include "engine/mesh/mesh_check.h"
#include "engine/util/error.h"

namespace ps::labelmap {

namespace {

std::string biff_text(const char* key) {
  char* e = biffGetDone(key);
  std::string s = e ? e : "unknown error";
  std::free(e);
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s;
}

bool in_set(int32_t label, const std::vector<int>& labels) {
  return std::find(labels.begin(), labels.end(), label) != labels.end();
}

}  // namespace

long long count_voxels(const LabelVolume& v, const std::vector<int>& labels) {
  long long n = 0;
  for (int32_t l : v.labels) n += in_set(l, labels);
  return n;
}

TriMesh label_surface(const LabelVolume& v, const std::vector<int>& labels, const SurfaceOptions& o,
                      const std::string& what, SurfaceStats* stats) {
  // the labelled voxels' index box
  int lo[3] = {v.size[0], v.size[1], v.size[2]}, hi[3] = {-1, -1, -1};
  long long voxels = 0;
  for (int k = 0; k < v.size[2]; ++k)
    for (int j = 0; j < v.size[1]; ++j)
      for (int i = 0; i < v.size[0]; ++i)
        if (in_set(v.labels[v.index(i, j, k)], labels)) {
          ++voxels;
          const int ijk[3] = {i, j, k};
          for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], ijk[a]);
            hi[a] = std::max(hi[a], ijk[a]);
          }
        }
  if (voxels == 0) throw InputError(v.file, 0, what, "no voxel carries this label (an empty organ)");

  // The mask in that box with a margin of zeros wide enough for the Gaussian's support, so that the
  // isosurface closes inside the grid even where the organ touches the image border.
  const Vec3 spacing_mm = v.spacing_m() * 1e3;
  double sigma_idx[3];
  int pad[3], n[3];
  for (int a = 0; a < 3; ++a) {
    sigma_idx[a] = o.smooth_sigma_mm / spacing_mm[a];
    pad[a] = static_cast<int>(std::ceil(3.0 * sigma_idx[a])) + 2;
    n[a] = hi[a] - lo[a] + 1 + 2 * pad[a];
  }
  std::vector<float> mask(static_cast<size_t>(n[0]) * n[1] * n[2], 0.0f);
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i)
        if (in_set(v.labels[v.index(i, j, k)], labels))
          mask[(i - lo[0] + pad[0]) + static_cast<size_t>(n[0]) * ((j - lo[1] + pad[1]) + static_cast<size_t>(n[1]) * (k - lo[2] + pad[2]))] = 1.0f;

  const size_t sizes[3] = {size_t(n[0]), size_t(n[1]), size_t(n[2])};
  std::unique_ptr<Nrrd, Nrrd* (*)(Nrrd*)> nmask(nrrdNew(), nrrdNix);
  std::unique_ptr<Nrrd, Nrrd* (*)(Nrrd*)> nsmooth(nrrdNew(), nrrdNuke);
  if (nrrdWrap_nva(nmask.get(), mask.data(), nrrdTypeFloat, 3, sizes))
    throw std::runtime_error("label map: " + biff_text(NRRD));
  const double unit[3] = {1.0, 1.0, 1.0};
  nrrdAxisInfoSet_nva(nmask.get(), nrrdAxisInfoSpacing, unit);
  int centers[3] = {nrrdCenterNode, nrrdCenterNode, nrrdCenterNode};
  nrrdAxisInfoSet_nva(nmask.get(), nrrdAxisInfoCenter, centers);
  {
    std::unique_ptr<NrrdResampleContext, NrrdResampleContext* (*)(NrrdResampleContext*)> rs(nrrdResampleContextNew(),
                                                                                             nrrdResampleContextNix);
    bool bad = nrrdResampleInputSet(rs.get(), nmask.get()) || nrrdResampleBoundarySet(rs.get(), nrrdBoundaryBleed) ||
               nrrdResampleTypeOutSet(rs.get(), nrrdTypeFloat) || nrrdResampleRenormalizeSet(rs.get(), AIR_TRUE);
    for (unsigned a = 0; a < 3 && !bad; ++a) {
      double parm[NRRD_KERNEL_PARMS_NUM] = {sigma_idx[a], 3.0};   // sigma [voxels], cut-off [sigmas]
      bad = nrrdResampleKernelSet(rs.get(), a, nrrdKernelGaussian, parm) || nrrdResampleSamplesSet(rs.get(), a, sizes[a]) ||
            nrrdResampleRangeFullSet(rs.get(), a);
    }
    if (bad || nrrdResampleExecute(rs.get(), nsmooth.get())) throw std::runtime_error("label map smoothing: " + biff_text(NRRD));
  }

  std::unique_ptr<seekContext, seekContext* (*)(seekContext*)> sc(seekContextNew(), seekContextNix);
  std::unique_ptr<limnPolyData, limnPolyData* (*)(limnPolyData*)> pld(limnPolyDataNew(), limnPolyDataNix);
  seekVerboseSet(sc.get(), 0);
  if (seekDataSet(sc.get(), nsmooth.get(), nullptr, 0) || seekTypeSet(sc.get(), seekTypeIsocontour) ||
      seekIsovalueSet(sc.get(), 0.5) || seekNormalsFindSet(sc.get(), AIR_FALSE) || seekUpdate(sc.get()) ||
      seekExtract(sc.get(), pld.get()))
    throw std::runtime_error("isosurface: " + biff_text(SEEK));

  // seek's vertices are in its gageShape's world space: back to the grid's index space (WtoI)
  const double* W = sc->shape->WtoI;
  TriMesh m;
  m.vertices.reserve(pld->xyzwNum);
  for (unsigned p = 0; p < pld->xyzwNum; ++p) {
    const float* q = pld->xyzw + 4 * p;
    double idx[4];
    for (int r = 0; r < 4; ++r) idx[r] = W[4 * r] * q[0] + W[4 * r + 1] * q[1] + W[4 * r + 2] * q[2] + W[4 * r + 3] * q[3];
    const double w = idx[3] != 0.0 ? idx[3] : 1.0;
    m.vertices.push_back(v.ras_m(idx[0] / w + lo[0] - pad[0], idx[1] / w + lo[1] - pad[1], idx[2] / w + lo[2] - pad[2]));
  }
  unsigned base = 0;
  for (unsigned p = 0; p < pld->primNum; ++p) {
    if (pld->type[p] == limnPrimitiveTriangles)
      for (unsigned t = 0; t + 2 < pld->icnt[p]; t += 3)
        m.faces.push_back({int(pld->indx[base + t]), int(pld->indx[base + t + 1]), int(pld->indx[base + t + 2])});
    base += pld->icnt[p];
  }
  if (stats) {
    stats->voxels = voxels;
    stats->voxel_volume_m3 = voxels * std::abs(v.index_to_ras_m.determinant());
    stats->isosurface_faces = static_cast<int>(m.faces.size());
  }
  if (m.faces.empty()) throw InputError(v.file, 0, what, "the isosurface is empty (an organ thinner than the smoothing)");
  try {
    m = repair_closed_surface(std::move(m), v.file);
    if (!check_mesh(m).valid_solid()) throw std::invalid_argument(check_mesh(m).summary());
    RemeshStats rs;
    m = remesh_to_spacing(m, o.edge_mm * 1e-3, &rs);
    if (stats) stats->remesh = rs;
  } catch (const InputError& e) {
    throw InputError(v.file, 0, what, "its isosurface is not a closed surface: " + e.message());
  } catch (const std::invalid_argument& e) {
    throw InputError(v.file, 0, what, std::string("its isosurface is not a closed surface: ") + e.what());
  }
  const MeshReport r = check_mesh(m);
  if (!r.valid_solid()) throw InputError(v.file, 0, what, "the remeshed surface is not a closed solid: " + r.summary());
  return m;
}

}  // namespace ps::labelmap
