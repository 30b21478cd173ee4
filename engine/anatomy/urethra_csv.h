// The prostatic urethra's centre line file, urethra.csv (written by `prostatesim make-anatomy`
// beside prostate.obj, engine/anatomy/anatomy_files.cpp): '#' comments, the header
// x_mm,y_mm,z_mm, then one point per row in millimetres, in the frame of the prostate's mesh
// file. Read once, at compile (engine/scenario/compile_urethra.cpp), into Model::urethra.
#pragma once
#include <string>
#include <vector>

#include "engine/util/vec.h"

namespace ps {

// Parses the text of a urethra.csv into points in metres (still in the mesh file's frame);
// InputError naming file:line and the column on a bad row or a missing header.
std::vector<Vec3> parse_urethra_csv(const std::string& text, const std::string& file);

}  // namespace ps
