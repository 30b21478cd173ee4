// Wavefront OBJ output of a triangle surface (positions and triangles only).
#pragma once
#include <string>

#include "engine/mesh/tri_mesh.h"

namespace ps {

// OBJ text: one "v x y z" per vertex (metres times scale_to_file_units, e.g. 1000 for mm) with
// enough digits to round-trip a double, then one 1-based "f a b c" per face.
std::string to_obj(const TriMesh& mesh, double scale_to_file_units = 1.0);

// Writes to_obj(mesh, scale) to path atomically; throws std::runtime_error naming the path.
void write_obj(const std::string& path, const TriMesh& mesh, double scale_to_file_units = 1.0);

}  // namespace ps
