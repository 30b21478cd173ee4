// What the renderer draws of the tissue, fixed for a compiled scene: each component's closed
// surface (particle indices and triangles), its colour and default transparency, markers for
// tagged particles (lesions, targets) and tubes that ride on the tissue (the urethra). Built
// once from the immutable Model; positions then come from each Snapshot (render/renderer.h).
// Reads Model data only: render/ knows nothing of the solver.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/anatomy/display_meshes.h"
#include "engine/draw/draw_sink.h"
#include "engine/model/role.h"
#include "engine/util/vec.h"

namespace ps {
struct Model;
}

namespace ps::render {

enum class OrganKind : uint8_t { Prostate, Bladder, Rectum, Fat, Bone, Other, SeminalVesicle };

struct RenderSurface {
  std::string name;                    // component name
  OrganKind kind = OrganKind::Other;
  std::vector<int> particles;          // [nv] particle of each vertex
  std::vector<uint32_t> indices;       // [3 nf] local vertex indices, outward CCW
  Rgba colour;                         // base colour; colour.a = default opacity
  // A shape carried by the tissue instead of particles (engine/anatomy/display_meshes.h: the
  // seminal vesicles, the pubic bone as drawn): `particles` stays empty and vertex v lies at
  // sum_k carry_weights[v][k] x[carry_particles[v][k]] + carry_offsets[v].
  std::vector<std::array<int, 4>> carry_particles;
  std::vector<std::array<float, 4>> carry_weights;
  std::vector<Vec3> carry_offsets;     // [m]
  std::vector<float> carry_rest;       // [3 nv] rest positions [m]
  size_t vertex_count() const { return carry_particles.empty() ? particles.size() : carry_particles.size(); }
};

// Particles of a tag drawn as spheres (lesion, target zone).
struct RenderMarkers {
  std::string name;
  std::vector<int> particles;
  double radius = 2e-3;                // [m]
  Rgba colour;
  DrawRole role = DrawRole::Lesion;
};

// A polyline carried by the tissue: point k = sum_j w_kj x_{p_kj} + offset_k (4 nearest
// particles of the host component at rest, inverse-distance weights), drawn as a tube.
struct RenderTube {
  std::string name;
  std::vector<std::array<int, 4>> particles;
  std::vector<std::array<float, 4>> weights;
  std::vector<Vec3> offsets;           // [m]
  double radius = 2.5e-3;              // [m]
  Rgba colour;
};

struct RenderScene {
  std::string name;
  std::vector<RenderSurface> surfaces;
  std::vector<RenderMarkers> markers;
  std::vector<RenderTube> tubes;
  std::vector<float> rest;             // [3n] rest positions [m] (displacement colouring)
  Vec3 focus = Vec3::Zero();           // what the cameras look at: prostate centre, else scene [m]
  double extent = 0.1;                 // radius that the preset views frame [m]
  int particle_count = 0;
};

// Style by the component's role (Component::role): prostate, bladder, rectum; fat and skin are
// drawn as fat; bone; anything else (urethra, lesion, gas, other) as Other.
OrganKind organ_kind(Role role);
Rgba organ_colour(OrganKind k);

// Builds the scene description. Lesion markers are the tags whose role is lesion; the urethra
// tube is the Model's centre line (Model::urethra, placed like the prostate's mesh at compile)
// bound to the first component whose role is prostate. `shapes` are drawn as carried surfaces
// (anatomy::display_meshes_for_scenario(): seminal vesicles, the pubic bone as bone).
RenderScene make_render_scene(const Model& model, const std::vector<anatomy::DisplayMesh>& shapes = {});
// The same with the scenario's display meshes (beside the gland's mesh; none without the files).
RenderScene make_render_scene(const ScenarioSpec& spec, const Model& model);


}  // namespace ps::render
