// The default anatomy as files (assets/anatomy/): one OBJ per organ in millimetres, the urethra
// path as CSV and named landmarks as YAML. The bytes are a pure function of the geometry:
// coordinates rounded to 0.1 um, no dates or versions, so `prostatesim make-anatomy` reproduces
// the committed assets exactly and a test can compare them.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "engine/anatomy/pelvis.h"

namespace ps::anatomy {

// Compact OBJ text: header comment lines ("# ..."), "v x y z" in millimetres with 4 decimals,
// then 1-based "f a b c".
std::string to_mm_obj(const TriMesh& mesh, const std::vector<std::string>& header);

struct AnatomyFile {
  std::string name;       // file name inside the anatomy folder
  std::string contents;
};

// prostate.obj, bladder.obj, rectum.obj, fat.obj, pubic_arch.obj, seminal_vesicles.obj,
// pubic_bone.obj, urethra.csv, calcifications.csv, landmarks.yaml.
std::vector<AnatomyFile> anatomy_files(const Anatomy& anatomy);

// Writes anatomy_files() into `folder` (created), each atomically. Throws std::runtime_error
// naming the path on failure.
void write_anatomy_files(const std::string& folder, const Anatomy& anatomy);

}  // namespace ps::anatomy
