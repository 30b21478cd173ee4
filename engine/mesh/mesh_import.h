// Import of triangle surfaces from OBJ, STL (ASCII and binary) and PLY files into a TriMesh in
// metres. Every problem with the file (unreadable, corrupt, empty, NaN, absurd size) is reported
// as an InputError naming the file; corrupt input never crashes or hangs the importer.
#pragma once
#include <string>

#include "engine/mesh/tri_mesh.h"
#include "engine/util/vec.h"

namespace ps {

struct MeshImportOptions {
  // Length unit of the coordinates in the file: "mm", "cm", "dm" or "m".
  std::string units = "m";
  // Placement applied after the unit conversion, in this order: scale, rotate, translate.
  Vec3 scale = Vec3::Ones();          // per-axis factor [-]; uniform: Vec3::Constant(s)
  Vec3 rotate_deg = Vec3::Zero();     // XYZ Euler angles [deg]: about x first, then y, then z
  Vec3 translate_m = Vec3::Zero();    // [m]
};

// Upper limits that keep a corrupt header from making the importer allocate gigabytes.
inline constexpr long long kMaxImportFaces = 5'000'000;
inline constexpr long long kMaxImportFileBytes = 1LL << 30;   // 1 GiB

// Reads all meshes of the file (merged into one surface, vertices at identical positions
// merged) and applies units and placement. The format is chosen by the extension (.obj, .stl,
// .ply, case-insensitive). The result is not repaired: see check_mesh/repair_closed_surface.
// Throws InputError(path, ...) on any problem, including a bounding-box diagonal after the unit
// conversion above 5 m or below 1 mm ("wrong units?").
TriMesh import_mesh(const std::string& path, const MeshImportOptions& opt = {});

// Metres per file unit for "mm", "cm", "dm", "m"; throws InputError(file, 0, "units", ...)
// for anything else.
double units_to_metres(const std::string& units, const std::string& file_for_errors);

// The placement import_mesh applies after the unit conversion, for a point already in metres:
// rotate(scale(p)) + translate. Data that lives in a mesh's frame (the urethra's centre line
// beside the prostate's mesh) is placed with it so that it stays where the mesh puts the organ.
Vec3 place_like_mesh(const Vec3& p_m, const MeshImportOptions& opt);

}  // namespace ps
