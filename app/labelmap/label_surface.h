// A closed, smooth, remeshed surface of the voxels carrying some labels: the mask is smoothed with
// a Gaussian (Teem's nrrd resampler), its 0.5 isosurface extracted with Teem's seek (marching
// cubes with a topologically consistent case table), then repaired, checked and remeshed with
// engine/mesh (repair_closed_surface, remesh_to_spacing).
#pragma once
#include <string>
#include <vector>

#include "app/labelmap/label_volume.h"
#include "engine/mesh/mesh_simplify.h"
#include "engine/mesh/tri_mesh.h"

namespace ps::labelmap {

struct SurfaceOptions {
  double smooth_sigma_mm = 1.0;   // Gaussian on the 0/1 mask before the isosurface [mm]
  double edge_mm = 3.0;           // remeshed edge length [mm]
};

struct SurfaceStats {
  long long voxels = 0;           // voxels carrying one of the labels
  double voxel_volume_m3 = 0.0;   // their volume [m^3]
  int isosurface_faces = 0;       // marching-cubes triangles before remeshing
  RemeshStats remesh;
};

// Voxels carrying one of `labels`; 0 when none does.
long long count_voxels(const LabelVolume& v, const std::vector<int>& labels);

// The surface in patient RAS [m], closed, 2-manifold and outward (check_mesh(..).valid_solid()).
// `what` names the organ and its label in errors. Throws InputError(v.file, 0, what, ...) when no
// voxel carries the labels or the surface cannot be made closed.
TriMesh label_surface(const LabelVolume& v, const std::vector<int>& labels, const SurfaceOptions& options,
                      const std::string& what, SurfaceStats* stats = nullptr);

}  // namespace ps::labelmap
