// Isodose lines and surfaces of a dose grid (dose_grid.h), for the trainee's views of the implant:
//  * on an image plane (a TRUS plane: its pixel raster placed in the world), the dose is sampled
//    (trilinear between voxel centres) every `step_px` pixels and each level's contour traced by
//    marching squares (the saddle cells resolved by the cell's mean); segments in pixel
//    coordinates (pixel centres at integers);
//  * in 3-D, one level's surface by marching tetrahedra (each voxel cell of eight neighbouring
//    voxel centres split into six tetrahedra around its main diagonal, so neighbouring cells
//    share their faces' splits and the surface is closed inside the grid): vertices shared
//    between cells, normals along the falling dose (outwards from the seeds).
// Millimetres, Gy. No GL: render/ draws what this returns.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "engine/dosimetry/dose_grid.h"

namespace ps::dosimetry {

// A dose grid and its values, immutable once built (shared between threads as a whole).
struct DoseField {
  GridSpec spec;
  std::vector<float> dose_gy;       // [spec.size()]
  double prescription_gy = 0.0;
  // Dose at p [Gy], trilinear between voxel centres; 0 outside the grid.
  double at(const Vec3& p_mm) const;
};

// The isodose levels the views draw, as fractions of the prescription.
inline constexpr std::array<double, 4> kIsodoseLevels = {0.5, 1.0, 1.5, 2.0};

// An image raster in the world: pixel (col, row) is at p00 + col dcol + row drow [mm].
struct PixelPlane {
  Vec3 p00_mm = Vec3::Zero(), dcol_mm = Vec3::UnitX(), drow_mm = -Vec3::UnitY();
  int width = 0, height = 0;        // [px]
};

struct IsoSegment {
  float x0, y0, x1, y1;             // pixel coordinates of the ends
  uint8_t level;                    // index into the levels given
};

// Contours of `levels_gy` on the plane; `out` cleared first. step_px: the sampling raster's pitch.
void plane_isodose(const DoseField& f, const PixelPlane& plane, const std::vector<double>& levels_gy, int step_px,
                   std::vector<IsoSegment>& out);

struct IsoSurface {
  std::vector<Vec3> vertices_mm;
  std::vector<Vec3> normals;        // unit, towards lower dose
  std::vector<std::array<int, 3>> faces;  // counter-clockwise seen from the lower dose side
};

// The surface D = level_gy. `stride` >= 1 takes every stride-th voxel centre (2: a 2 mm surface
// from the 1 mm grid, a quarter of the triangles).
IsoSurface isodose_surface(const DoseField& f, double level_gy, int stride = 1);
// The stride the views use (window, replay frames): a 2 mm surface, ~16 k triangles for a 36 cc
// gland instead of ~65 k, and an eighth of the cells to visit (bench/dosimetry_bench.cpp).
inline constexpr int kViewSurfaceStride = 2;

}  // namespace ps::dosimetry
