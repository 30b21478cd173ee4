// Which voxels of a dose grid lie in each structure: one bit per structure in a byte per voxel.
// A closed surface is filled by scanlines along x (crossings of each voxel row with the
// triangles, inside between odd and even crossings); a tube (the urethra) by distance to its
// centre line.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "engine/dosimetry/dose_grid.h"

namespace ps::dosimetry {

enum StructureBit : uint8_t { kProstate = 1, kUrethra = 2, kRectum = 4 };

// Sets `bit` in mask (size spec.size()) for the voxel centres inside the closed surface.
void fill_closed_surface(const GridSpec& spec, const std::vector<Vec3>& vertices_mm,
                         const std::vector<std::array<int, 3>>& faces, uint8_t bit, std::vector<uint8_t>& mask);
// Sets `bit` for the voxel centres within radius of the polyline.
void fill_tube(const GridSpec& spec, const std::vector<Vec3>& line_mm, double radius_mm, uint8_t bit,
               std::vector<uint8_t>& mask);
// Clears `bit` where `other` is set: keeps the rectum out of the gland where the two surfaces
// overlap (the urethra stays in the gland, as it does clinically).
void clear_where(std::vector<uint8_t>& mask, uint8_t bit, uint8_t other);

}  // namespace ps::dosimetry
