// Shapes that are drawn and imaged but not simulated (no particles): the seminal vesicles and the
// pubic bone as the 3D view draws it. `prostatesim make-anatomy` writes them beside the prostate's
// mesh (assets/anatomy/seminal_vesicles.obj, pubic_bone.obj); a scenario whose gland mesh has the
// files beside it gets them, placed by the gland mesh's units, scale, rotation and translation like
// the urethra (engine/scenario/compile_urethra.cpp). Each vertex is carried by the tissue: the
// inverse-distance mean of its 4 nearest particles at rest plus a fixed offset, so the shape moves
// and deforms with what surrounds it. The ultrasound images the vesicles (engine/ultrasound); the
// renderer draws both (render/render_scene.h).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/mesh/tri_mesh.h"
#include "engine/model/model.h"
#include "engine/spec/scenario_spec.h"

namespace ps::anatomy {

// A vertex carried by the tissue: its 4 nearest particles at rest among `candidates` (searched in
// the order given), inverse-distance weights (sum 1, in float as the views use them) and the
// vertex's offset from their weighted mean, so that the rest pose is reproduced.
struct CarriedVertex {
  std::array<int, 4> ids{};
  std::array<float, 4> weights{};
  Vec3 offset = Vec3::Zero();  // [m]
};
CarriedVertex carry_vertex(const Vec3& q, const std::vector<Vec3>& rest, const std::vector<int>& candidates);

struct DisplayMesh {
  enum Kind : uint8_t { SeminalVesicle, Bone };
  std::string name;                           // e.g. "seminal_vesicle_right", "pubic_bone"
  Kind kind = SeminalVesicle;
  TriMesh mesh;                               // at rest [m]; a vesicle: one closed outward surface
  std::vector<std::array<int, 4>> carriers;   // [vertices] the 4 particles that carry each vertex
  std::vector<std::array<float, 4>> weights;  // [vertices] their weights (sum 1)
  std::vector<Vec3> offsets;                  // [vertices] vertex - weighted mean at rest [m]
  // current vertex v from positions x (Snapshot::x layout, 3 floats per particle) [m]
  Vec3 vertex(const float* x, size_t v) const {
    Vec3 q = offsets[v];
    for (int k = 0; k < 4; ++k) {
      const int p = carriers[v][k];
      q += static_cast<double>(weights[v][k]) * Vec3(x[3 * p], x[3 * p + 1], x[3 * p + 2]);
    }
    return q;
  }
};

// Splits `mesh` into its connected parts (faces sharing vertices), each with its own vertices.
std::vector<TriMesh> connected_parts(const TriMesh& mesh);

// The display meshes of a compiled scenario: the seminal vesicles (one DisplayMesh per vesicle,
// carried by the non-rigid tissue) and the pubic bone (carried by the bone component, else any
// particle), from the files beside the gland's mesh; none when the files are absent. InputError
// (file) on an unreadable file.
std::vector<DisplayMesh> display_meshes_for_scenario(const ScenarioSpec& spec, const Model& model);

}  // namespace ps::anatomy
